// Scene gates (body_gates.hpp) on constructed scenes with a known defect.
#include <gtest/gtest.h>

#include <cmath>

#include "owval/compare/parity.hpp"

namespace owval::compare {
namespace {

// A straight worm along z (midline rings of 8 particles, radius `radius` cu, one per bin
// 51..149), over 5 frames, sinking by `sink_cu` per frame.
Trajectory Worm(float radius, float sink_cu) {
  Trajectory t;
  t.box = {0, 40, 0, 40, 0, 60};
  t.time_step_s = 2e-5;
  for (int bin = 51; bin < 150; ++bin)
    for (int k = 0; k < 8; ++k) t.type.push_back(2.1f + float(bin - 1) * 1e-4f + 2e-5f);
  for (int f = 0; f < 5; ++f) {
    std::vector<float> frame;
    for (int bin = 51; bin < 150; ++bin)
      for (int k = 0; k < 8; ++k) {
        const double angle = 2 * M_PI * k / 8;
        frame.insert(frame.end(), {10 + radius * float(std::cos(angle)),
                                   20 - sink_cu * float(f) + radius * float(std::sin(angle)),
                                   2 + 0.5f * float(bin - 51)});
      }
    t.AppendFrame(f * 1e-3, frame.data());
  }
  return t;
}

GateStatus StatusOf(const ParityReport& r, const std::string& gate) {
  const Gate* g = r.gate(gate);
  return g ? g->status : GateStatus::kNotApplicable;
}

TEST(BodyGates, WormGatesPassForTheSameWormAndNameASwollenOne) {
  const Trajectory ref = Worm(1.5f, 0);
  const ParityReport same = CompareTrajectories(ref, ref, {});
  ASSERT_NE(same.gate("worm.cross_section_diameter"), nullptr);
  EXPECT_EQ(StatusOf(same, "worm.span"), GateStatus::kPass);
  EXPECT_EQ(StatusOf(same, "worm.cross_section_diameter"), GateStatus::kPass);
  const ParityReport swollen = CompareTrajectories(ref, Worm(1.8f, 0), {});
  EXPECT_EQ(StatusOf(swollen, "worm.cross_section_diameter"), GateStatus::kFail);
  EXPECT_NEAR(swollen.gate("worm.cross_section_diameter")->value, 0.2, 1e-5);
  EXPECT_EQ(StatusOf(swollen, "worm.span"), GateStatus::kPass);
  // Sinking 1 cu a frame: 4 cu by the last frame, 4/60 of the box > 0.05.
  const ParityReport sinking = CompareTrajectories(ref, Worm(1.5f, 1.0f), {});
  EXPECT_EQ(StatusOf(sinking, "worm.centre_of_mass"), GateStatus::kFail);
  EXPECT_NEAR(sinking.gate("worm.centre_of_mass")->value, 4.0 / 60, 1e-5);
}

// An elastic sheet at y = 10 across the box, 100 liquid particles above it; `leaked` of them
// below it from frame 1 on.
Trajectory Sheet(int leaked) {
  Trajectory t;
  t.box = {0, 20, 0, 40, 0, 20};
  t.time_step_s = 2e-5;
  for (int i = 0; i < 25; ++i) t.type.push_back(2.1f);
  for (int i = 0; i < 100; ++i) t.type.push_back(1.1f);
  for (int f = 0; f < 3; ++f) {
    std::vector<float> frame;
    for (int i = 0; i < 25; ++i)
      frame.insert(frame.end(), {float(i % 5) * 4, 10, float(i / 5) * 4});
    for (int i = 0; i < 100; ++i)
      frame.insert(frame.end(),
                   {float(i % 10), (f > 0 && i < leaked) ? 5.0f : 20.0f, float(i / 10)});
    t.AppendFrame(f * 1e-3, frame.data());
  }
  return t;
}

TEST(BodyGates, MembraneGateNamesLiquidLeakingThroughTheSheet) {
  const ParityReport tight = CompareTrajectories(Sheet(0), Sheet(2), {});
  EXPECT_EQ(StatusOf(tight, "liquid.fraction_above_membrane"), GateStatus::kPass);
  const ParityReport leaking = CompareTrajectories(Sheet(0), Sheet(30), {});
  EXPECT_EQ(StatusOf(leaking, "liquid.fraction_above_membrane"), GateStatus::kFail);
  EXPECT_NEAR(leaking.gate("liquid.fraction_above_membrane")->value, 0.3, 1e-9);
  // A scene without a sheet or a worm gets neither kind of gate.
  EXPECT_EQ(
      CompareTrajectories(Worm(1.5f, 0), Worm(1.5f, 0), {}).gate("liquid.fraction_above_membrane"),
      nullptr);
}

}  // namespace
}  // namespace owval::compare
