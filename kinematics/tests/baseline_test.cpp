#include "owval/kinematics/baseline.hpp"

#include <gtest/gtest.h>

namespace owval::kinematics {
namespace {

Report Swimmer(double speed, double frequency, double wavelength) {
  Report r;
  r.midbody_speed_mm_s = speed;
  r.frequency_hz = frequency;
  r.wavelength_mm = wavelength;
  r.regime = Regime::kSwimming;
  return r;
}

TEST(Tier3, ValuesInsideTheWidenedRangePass) {
  // Swimming: 0.26-0.41 mm/s, 1.76-1.83 Hz, 0.43-0.47 mm; +-15% widens to 0.221-0.4715 mm/s,
  // 1.496-2.1045 Hz, 0.3655-0.5405 mm.
  const std::vector<Tier3Check> c = CheckTier3(Swimmer(0.45, 1.5, 0.54));
  ASSERT_EQ(c.size(), 3u);
  for (const Tier3Check& check : c) EXPECT_TRUE(check.pass) << check.detail;
  EXPECT_EQ(c[0].detail, "0.45 mm/s, baseline (swimming) 0.26-0.41 mm/s, +-15%: 0.221-0.4715");
}

TEST(Tier3, ValuesOutsideFailAndMissingValuesFail) {
  Report r = Swimmer(0.48, 2.11, 0.36);
  for (const Tier3Check& check : CheckTier3(r)) EXPECT_FALSE(check.pass) << check.detail;
  r.frequency_hz.reset();
  r.frequency_note = "run holds less than one cycle";
  const std::vector<Tier3Check> c = CheckTier3(r);
  EXPECT_FALSE(c[1].pass);
  EXPECT_NE(c[1].detail.find("no bend frequency: run holds less than one cycle"),
            std::string::npos);
}

// Palyanov's worms go forward: a backward speed of the baseline's magnitude is not its speed
// (the magnitude alone passed it: -0.45 mm/s was within 0.221-0.4715).
TEST(Tier3, ABackwardSpeedFailsWhateverItsMagnitude) {
  const std::vector<Tier3Check> c = CheckTier3(Swimmer(-0.45, 1.5, 0.54));
  EXPECT_FALSE(c[0].pass);
  EXPECT_EQ(c[0].detail,
            "-0.45 mm/s (backwards), baseline (swimming) 0.26-0.41 mm/s, +-15%: 0.221-0.4715");
  EXPECT_TRUE(c[1].pass && c[2].pass);
}

// The time-reversed reference swims backwards at its pace: the speed parity compared magnitudes
// and found them 0.00% apart.
TEST(Tier3, KinematicsParityComparesTheSpeedWithItsDirection) {
  const std::vector<AgreementCheck> c =
      CompareKinematics(Swimmer(0.30, 1.80, 0.45), Swimmer(-0.30, 1.80, 0.45));
  EXPECT_FALSE(c[0].pass);
  EXPECT_EQ(c[0].detail, "reference 0.3, candidate -0.3: 200.00% apart (max 5%)");
  EXPECT_TRUE(c[1].pass && c[2].pass);
}

TEST(Tier3, TheRegimeChoosesTheBaseline) {
  // 0.14 mm/s, 0.365 Hz, 0.67 mm: a crawler; judged as a swimmer it fails every metric.
  Report r = Swimmer(0.14, 0.365, 0.67);
  r.regime = Regime::kCrawling;
  for (const Tier3Check& check : CheckTier3(r)) EXPECT_TRUE(check.pass) << check.detail;
  for (const Tier3Check& check : CheckTier3(r, Regime::kSwimming)) EXPECT_FALSE(check.pass);
  r.regime = Regime::kUndetermined;
  for (const Tier3Check& check : CheckTier3(r)) EXPECT_FALSE(check.pass);
}

TEST(Tier3, KinematicsOfTwoBackendsAgreeWithin5Percent) {
  const Report a = Swimmer(0.30, 1.80, 0.45);
  for (const AgreementCheck& c : CompareKinematics(a, Swimmer(0.314, 1.711, 0.472)))
    EXPECT_TRUE(c.pass) << c.detail;
  const std::vector<AgreementCheck> c = CompareKinematics(a, Swimmer(0.30, 1.80, 0.48));
  EXPECT_TRUE(c[0].pass && c[1].pass);
  EXPECT_FALSE(c[2].pass) << c[2].detail;
}

}  // namespace
}  // namespace owval::kinematics
