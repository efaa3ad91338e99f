// The liquid_packing gate: the liquid's kernel sum from positions, its median and upper quartile
// over the liquid averaged over the paired frames, against the reference's. Sibernetic's demo1
// dilated by 1% about the box centre (its liquid 3% less dense) passed every other gate; honest
// PCISPH reruns whose chaos diverged stay within 0.5% (docs/checklist.md, "liquid_packing").
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

#include "edited_runs.hpp"
#include "liquid_packing.hpp"
#include "owval/compare/parity.hpp"
#include "owval/testing/reference_runs.hpp"

namespace owval::compare {
namespace {

using testing_edits::HonestDemo1Rerun;
using testing_edits::ScaledAboutTheBoxCentre;

ParityReport Demo1ScaledFromFrameOne(double factor) {
  const Trajectory& demo1 = *testing::SiberneticDemo1Run();
  return CompareTrajectories(demo1, ScaledAboutTheBoxCentre(demo1, factor, 1), {});
}

TEST(LiquidPacking, KernelSumCountsEveryKindOfNeighbourAndItself) {
  // Liquid 0 with a liquid, an elastic and a boundary particle at h/2, h·0.9 and 1.5·h.
  Trajectory t;
  t.type = {1.1f, 1.1f, 2.1f, 3.1f};
  const float x[12] = {0, 0, 0, 1, 0, 0, 0, -1.8f, 0, 0, 0, 1.5f};
  t.AppendFrame(0, x);
  const internal::PackingSummary s = internal::MeasurePacking({t, 0}, {0}, 2.0);
  // (1 - r^2/h^2)^3 each: 1 (itself), 0.75^3, 0.19^3 (float's 1.8), 0.4375^3.
  const double expected = 1 + std::pow(0.75, 3) + std::pow(1 - std::pow(double(1.8f) / 2, 2), 3) +
                          std::pow(1 - 0.5625, 3);
  EXPECT_NEAR(s.median, expected, 1e-12);
  EXPECT_NEAR(s.upper_quartile, expected, 1e-12);
}

TEST(LiquidPacking, ASceneWithoutLiquidIsNotApplicable) {
  const Trajectory& run = testing::BundledOneSprigRun();
  const ParityReport r = CompareTrajectories(run, run, {});
  const Gate& g = *r.gate("liquid_packing");
  EXPECT_EQ(g.status, GateStatus::kNotApplicable);
  EXPECT_EQ(g.detail, "the scene has no liquid");
  EXPECT_TRUE(r.pass()) << r.FailedGates();
}

TEST(LiquidPackingParity, ReferenceAgainstItselfMeasuresZero) {
  OWVAL_REQUIRE_DEMO1();
  const Trajectory& demo1 = *testing::SiberneticDemo1Run();
  const ParityReport r = CompareTrajectories(demo1, demo1, {});
  const Gate& g = *r.gate("liquid_packing");
  EXPECT_EQ(g.value, 0.0);
  EXPECT_EQ(g.status, GateStatus::kPass);
  EXPECT_EQ(g.threshold.value, 0.01);  // the default
  // Support twice the median spacing (1.67 cu, r0): Sibernetic's h.
  EXPECT_NE(g.detail.find("candidate 6.0968, reference 6.0968 (+0.00%)"), std::string::npos)
      << g.detail;
  EXPECT_NE(g.detail.find("support 3.34 cu"), std::string::npos) << g.detail;
  EXPECT_TRUE(r.pass()) << r.FailedGates();
}

TEST(LiquidPackingParity, Demo1DilatedByOnePercentFailsOnlyThis) {
  OWVAL_REQUIRE_DEMO1();
  const ParityReport r = Demo1ScaledFromFrameOne(1.01);
  EXPECT_EQ(r.FailedGates(), "liquid_packing");  // every motion gate admits 0.67 cu
  const Gate& g = *r.gate("liquid_packing");
  // Median -2.27%, upper quartile -2.35% (the self term, 1 of 6.1, does not dilate).
  EXPECT_NEAR(g.value, 0.0235, 0.0005);
  EXPECT_NE(g.detail.find("(-2.35%)"), std::string::npos) << g.detail;
  EXPECT_NE(g.detail.find("the frame differing most: reference frame "), std::string::npos);
}

TEST(LiquidPackingParity, Demo1CompressedByOnePercentFails) {
  OWVAL_REQUIRE_DEMO1();
  const ParityReport r = Demo1ScaledFromFrameOne(0.99);
  const Gate& g = *r.gate("liquid_packing");
  EXPECT_EQ(g.status, GateStatus::kFail);
  EXPECT_NEAR(g.value, 0.0259, 0.0005);  // +2.56% median, +2.59% upper quartile
  EXPECT_NE(g.detail.find("(+2.59%)"), std::string::npos) << g.detail;
}

TEST(LiquidPackingParity, Demo1DilatedByAThirdOfAPercentCannotBeToldApart) {
  OWVAL_REQUIRE_DEMO1();
  // The stated limit: 0.75% in the kernel sum, within what honest reruns differ by.
  const ParityReport r = Demo1ScaledFromFrameOne(1.003);
  const Gate& g = *r.gate("liquid_packing");
  EXPECT_EQ(g.status, GateStatus::kPass) << g.value << ": " << g.detail;
  EXPECT_NEAR(g.value, 0.0075, 0.0005);
}

TEST(LiquidPackingParity, AnHonestPerturbedRerunPassesAndTheSameDilatedFails) {
  OWVAL_REQUIRE_DEMO1();
  const Trajectory& demo1 = *testing::SiberneticDemo1Run();
  const Trajectory rerun = HonestDemo1Rerun(0.05);  // 125 frames
  const ParityReport honest_report = CompareTrajectories(demo1, rerun, {});
  const Gate& honest = *honest_report.gate("liquid_packing");
  EXPECT_EQ(honest.status, GateStatus::kPass) << honest.value << ": " << honest.detail;
  EXPECT_GT(honest.value, 1e-3);  // diverged: not the reference's own frames
  const ParityReport dilated_report =
      CompareTrajectories(demo1, ScaledAboutTheBoxCentre(rerun, 1.01, 1), {});
  const Gate& dilated = *dilated_report.gate("liquid_packing");
  EXPECT_EQ(dilated.status, GateStatus::kFail) << dilated.value << ": " << dilated.detail;
}

}  // namespace
}  // namespace owval::compare
