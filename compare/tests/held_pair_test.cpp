// The held_pair gate: an honest near-encounter is brief, a leak or an edit holds its pair close
// for the rest of the run. Sibernetic's demo1 liquid holds pairs at a quarter of r0 (0.44 cu)
// for a tenth of the run itself, so a liquid particle held at 0.1 r0 from its neighbour is 2.6
// times closer than that and fails, one held at 0.3 r0 cannot be told apart and passes
// (docs/checklist.md, "held_pair"). r0 = 1.67 cu.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "edited_runs.hpp"
#include "held_pairs.hpp"
#include "owval/compare/parity.hpp"
#include "owval/testing/reference_runs.hpp"
#include "owval/trajectory/formats.hpp"

namespace owval::compare {
namespace {

constexpr double kR0Cu = 1.67;

using testing_edits::HeldAt;

// Liquid particle 300 held `fraction_of_r0` from its neighbour 301 from frame 1 to the end.
ParityReport HeldForTheRestOfTheRun(double fraction_of_r0) {
  const Trajectory& demo1 = *testing::SiberneticDemo1Run();
  return CompareTrajectories(
      demo1, HeldAt(demo1, 300, 301, fraction_of_r0 * kR0Cu, 1, demo1.frame_count()), {});
}

TEST(HeldPair, ReferenceAgainstItselfMeasuresOne) {
  OWVAL_REQUIRE_DEMO1();
  const Trajectory& demo1 = *testing::SiberneticDemo1Run();
  const ParityReport r = CompareTrajectories(demo1, demo1, {});
  const Gate& g = *r.gate("held_pair");
  EXPECT_EQ(g.value, 1.0);
  EXPECT_EQ(g.status, GateStatus::kPass);
  // The reference's own held liquid pair: within 0.4553 cu (the ladder level 0.835·2^(-7/8)) (0.27
  // r0) for 50 of its 500 frames.
  EXPECT_EQ(g.detail.rfind(
                "liquid-liquid: candidate within 0.4553 cu (particles 238 liquid and 285 liquid, "
                "reference frames 195 to 244)",
                0),
            0u)
      << g.detail;
  EXPECT_NE(g.detail.find("held = 50 consecutive paired frames, cap 0.835 cu (half the "
                          "reference's median spacing, 1.67 cu)"),
            std::string::npos)
      << g.detail;
  EXPECT_TRUE(r.pass()) << r.FailedGates();
}

TEST(HeldPair, Demo1WithALiquidParticleHeldAtATenthOfR0Fails) {
  OWVAL_REQUIRE_DEMO1();
  const ParityReport r = HeldForTheRestOfTheRun(0.1);
  // closest_approach passes: 0.167 cu is farther than the reference's closest, 0.049 cu.
  EXPECT_EQ(r.FailedGates(), "held_pair");
  const Gate& g = *r.gate("held_pair");
  EXPECT_EQ(g.threshold.value, 2.0);  // the default
  // 0.4553 cu over 0.1755 cu, the ladder level holding 0.167 cu: 2^(11/8).
  EXPECT_NEAR(g.value, std::exp2(11.0 / 8), 1e-9);
  EXPECT_EQ(g.status, GateStatus::kFail);
  EXPECT_NE(g.detail.find("candidate within 0.1755 cu (particles 300 liquid and 301 liquid, "
                          "reference frames 1 to 50)"),
            std::string::npos)
      << g.detail;
}

TEST(HeldPair, Demo1WithALiquidParticleHeldAtAHundredthOfR0Fails) {
  OWVAL_REQUIRE_DEMO1();
  const ParityReport r = HeldForTheRestOfTheRun(0.01);
  EXPECT_EQ(r.FailedGates(), "held_pair");  // closest_approach: 2.96, under its 10
  const Gate& g = *r.gate("held_pair");
  EXPECT_EQ(g.status, GateStatus::kFail);
  EXPECT_GT(g.value, 20.0);
  EXPECT_LT(g.value, 30.0);
}

TEST(HeldPair, Demo1WithALiquidParticleHeldAtThreeTenthsOfR0CannotBeToldApart) {
  OWVAL_REQUIRE_DEMO1();
  // The gate's stated limit: Sibernetic's liquid holds its own pairs at 0.27 r0 for 50 frames,
  // so a pair held at 0.3 r0 is no closer than the reference's own and passes.
  const ParityReport r = HeldForTheRestOfTheRun(0.3);
  const Gate& g = *r.gate("held_pair");
  EXPECT_EQ(g.status, GateStatus::kPass) << g.value << ": " << g.detail;
  EXPECT_LE(g.value, 1.0);
}

TEST(HeldPair, APairCloseForTwoFramesPasses) {
  OWVAL_REQUIRE_DEMO1();
  // The same hundredth of r0 as above, for two frames: an encounter, not a hold.
  const Trajectory& demo1 = *testing::SiberneticDemo1Run();
  const ParityReport r =
      CompareTrajectories(demo1, HeldAt(demo1, 300, 301, 0.01 * kR0Cu, 200, 202), {});
  const Gate& g = *r.gate("held_pair");
  EXPECT_EQ(g.status, GateStatus::kPass) << g.value << ": " << g.detail;
  EXPECT_LE(g.value, 1.0);
}

TEST(HeldPair, AHoldShorterThanATenthOfTheRunPassesAndOneAsLongFails) {
  OWVAL_REQUIRE_DEMO1();
  const Trajectory& demo1 = *testing::SiberneticDemo1Run();
  for (const auto& [frames, status] :
       {std::pair{49, GateStatus::kPass}, std::pair{50, GateStatus::kFail}}) {
    const ParityReport r = CompareTrajectories(
        demo1, HeldAt(demo1, 300, 301, 0.01 * kR0Cu, 300, 300 + std::size_t(frames)), {});
    EXPECT_EQ(r.gate("held_pair")->status, status) << frames << " frames";
  }
}

TEST(HeldPair, TheWormsLiquidHeldAtATenthOfR0FailsThoughItsBodyHoldsPairsCloser) {
  // The worm's body holds elastic pairs (11 and 15, ...) 0.12 cu apart, 0.07 r0, for the whole
  // run by construction: compared kind by kind, a liquid pair held at 0.1 r0 is still caught.
  const std::filesystem::path path =
      std::filesystem::path(OWVAL_SHARED_DIR) / "reference/worm_alone_0.6s/position_buffer.txt.gz";
  if (!std::filesystem::exists(path)) {
    if (std::getenv("OWVAL_REQUIRE_REFERENCE")) FAIL() << "no " << path;
    GTEST_SKIP() << "no " << path;
  }
  TextReadOptions quiet;
  quiet.quiet = true;
  const Trajectory worm = ReadTrajectory(path, quiet);
  const ParityReport r =
      CompareTrajectories(worm, HeldAt(worm, 2600, 2594, 0.1 * kR0Cu, 1, worm.frame_count()), {});
  EXPECT_EQ(r.FailedGates(), "held_pair");
  const Gate& g = *r.gate("held_pair");
  EXPECT_NEAR(g.value, std::exp2(12.0 / 8), 1e-9);  // 0.5129 cu over 0.1813 cu
  EXPECT_EQ(g.detail.rfind("liquid-liquid: candidate within 0.1813 cu (particles 2594 liquid and "
                           "2600 liquid, reference frames 1 to 20)",
                           0),
            0u)
      << g.detail;
}

TEST(HeldPair, OneSprigsSpringHeldByItsAnchorIsNoNearContact) {
  // One elastic particle on a spring from its anchor, 12.5 cu away: a pair held by construction
  // at the scene's spacing, so beyond the cap (half of it): nothing is held close.
  const Trajectory& run = testing::BundledOneSprigRun();
  const ParityReport r = CompareTrajectories(run, run, {});
  const Gate& g = *r.gate("held_pair");
  EXPECT_EQ(g.status, GateStatus::kPass) << g.detail;
  EXPECT_EQ(g.value, 0.0);
  EXPECT_EQ(g.detail.rfind("the candidate holds no pair within the cap; held = 250 consecutive "
                           "paired frames, cap 6.262 cu (half the reference's median spacing, "
                           "12.52 cu)",
                           0),
            0u)
      << g.detail;
}

TEST(HeldPairs, LadderRunsCountConsecutiveFramesWithinEachLevel) {
  // Three particles in a line; 0 and 1 at 0.1 cu, held for 3 frames, then apart.
  Trajectory t;
  t.type = {1.1f, 1.1f, 1.1f};
  const double spacing_cu[5] = {0.1, 0.1, 0.1, 5, 0.1};
  for (std::size_t f = 0; f < 5; ++f) {
    const float x[9] = {0, 0, 0, float(spacing_cu[f]), 0, 0, 20, 0, 0};
    t.AppendFrame(0.1 * double(f), x);
  }
  internal::HeldPairs h(1.0, 3);
  const std::vector<std::size_t> moving = {0, 1, 2};
  for (std::size_t f = 0; f < 5; ++f) h.Observe({t, f}, moving, f);
  const internal::HeldPairs::Held& held = h.held()[3];  // liquid-liquid
  // 0.1 cu is 3.32 octaves under the 1 cu cap: level 26 (0.105 cu) holds it, 27 does not.
  EXPECT_EQ(held.level, 26);
  EXPECT_NEAR(h.LevelDistanceCu(held.level), std::exp2(-26.0 / 8), 1e-12);
  EXPECT_EQ(held.first, 0u);
  EXPECT_EQ(held.second, 1u);
  EXPECT_EQ(held.end_pair, 2u);
  EXPECT_EQ(h.held()[0].level, -1);  // no elastic particle
}

}  // namespace
}  // namespace owval::compare
