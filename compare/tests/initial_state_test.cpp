// The initial_state gate: a candidate run of the same configuration starts where the reference
// starts, particle for particle, to the files' printed precision (6 significant digits). Before
// it, demo1's reference with one liquid particle on its neighbour's place in every frame passed
// every gate (liquid.worst_particle 0.0471 < 0.05), and so did a candidate started elsewhere.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <limits>

#include "owval/compare/parity.hpp"
#include "owval/testing/reference_runs.hpp"
#include "owval/trajectory/formats.hpp"

namespace owval::compare {
namespace {

TEST(InitialState, ReferenceAgainstItselfIsZero) {
  const ParityReport r =
      CompareTrajectories(testing::BundledOneSprigRun(), testing::BundledOneSprigRun(), {});
  ASSERT_NE(r.gate("initial_state"), nullptr);
  EXPECT_EQ(r.gate("initial_state")->status, GateStatus::kPass);
  EXPECT_EQ(r.gate("initial_state")->value, 0.0);
  EXPECT_EQ(r.gate("initial_state")->detail, "every coordinate equal at 0 s");
}

TEST(InitialState, Demo1WithOneLiquidParticleOnANeighboursPlaceFromFrameZeroFails) {
  OWVAL_REQUIRE_DEMO1();
  // Liquid particle 300 on its neighbour 301's place in every frame: 4.2 cu at worst, 4.7% of
  // the box, under liquid.worst_particle's 5%; at frame 0 the two are 1.67 cu apart, where the
  // printed precision allows 1e-5 of the coordinate (4.7e-4 cu): 3,555 allowances.
  Trajectory copied = *testing::SiberneticDemo1Run();
  for (std::size_t f = 0; f < copied.frame_count(); ++f)
    for (int a = 0; a < 3; ++a) copied.position(f, 300)[a] = copied.position(f, 301)[a];
  const ParityReport r = CompareTrajectories(*testing::SiberneticDemo1Run(), copied, {});
  // Two particles in one place: closest_approach fails too (closest_approach_test.cpp).
  EXPECT_EQ(r.FailedGates(), "initial_state, closest_approach, held_pair");
  const Gate& g = *r.gate("initial_state");
  EXPECT_NEAR(g.value, 3555, 1);
  EXPECT_NE(g.detail.find("particle 300 (liquid)"), std::string::npos) << g.detail;
  EXPECT_LT(r.gate("liquid.worst_particle")->value, 0.05);
}

TEST(InitialState, OneParticleStartedAThousandthOfACuAwayFails) {
  // one_sprig's particle 0 (y = 20.04 at the start) 1e-3 cu higher at frame 0 only: beyond two
  // 6-digit roundings (2e-4 cu, with float32's 3e-6 at the box's 33.4 cu); no other gate sees it.
  Trajectory moved = testing::BundledOneSprigRun();
  const double y = moved.position(0, 0)[1];
  ASSERT_NEAR(y, 20.04, 1e-3);
  moved.position(0, 0)[1] += 1e-3f;
  const ParityReport r = CompareTrajectories(testing::BundledOneSprigRun(), moved, {});
  EXPECT_EQ(r.FailedGates(), "initial_state");
  EXPECT_NEAR(r.gate("initial_state")->value, 1e-3 / (1e-5 * (y + 1e-3) + 1e-7 * 33.4), 0.01);
}

TEST(InitialState, RoundingToSixSignificantDigitsPasses) {
  // Every coordinate rounded to 6 significant digits, as a second print of the same state.
  Trajectory printed = testing::BundledOneSprigRun();
  for (std::size_t p = 0; p < printed.particle_count(); ++p)
    for (int a = 0; a < 3; ++a) {
      float& x = printed.position(0, p)[a];
      char text[32];
      std::snprintf(text, sizeof text, "%.6g", double(x) * (1 + 4e-6));
      x = std::strtof(text, nullptr);
    }
  const ParityReport r = CompareTrajectories(testing::BundledOneSprigRun(), printed, {});
  EXPECT_EQ(r.gate("initial_state")->status, GateStatus::kPass) << r.gate("initial_state")->value;
}

TEST(InitialState, ACandidateWithoutTheReferencesFirstFrameFails) {
  // The candidate's frames from the reference's second frame on: within the window gate's 2%,
  // but where it started is unknown.
  const Trajectory& ref = testing::BundledOneSprigRun();
  Trajectory late = ref;
  late.positions.erase(late.positions.begin(),
                       late.positions.begin() + std::ptrdiff_t(ref.particle_count() * 3));
  late.time_s.erase(late.time_s.begin());
  const ParityReport r = CompareTrajectories(ref, late, {});
  const Gate& g = *r.gate("initial_state");
  EXPECT_EQ(g.status, GateStatus::kFail);
  EXPECT_NE(g.detail.find("no frame at the reference's first time"), std::string::npos) << g.detail;
}

TEST(InitialState, ANonFiniteFirstFrameFails) {
  Trajectory broken = testing::BundledOneSprigRun();
  broken.position(0, 3)[0] = std::numeric_limits<float>::quiet_NaN();
  const ParityReport r = CompareTrajectories(testing::BundledOneSprigRun(), broken, {});
  EXPECT_EQ(r.gate("initial_state")->status, GateStatus::kFail);
}

}  // namespace
}  // namespace owval::compare
