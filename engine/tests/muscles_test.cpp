// Muscle signals against the closed form of main_sim.MuscleSimulation (physics sheet §4).
#include <gtest/gtest.h>

#include <cmath>

#include "owval/engine/muscles.hpp"

namespace owval::engine {
namespace {

const double kPi = 3.14159265358979323846;
const double kWeights[12] = {0.81, 0.90, 0.97, 1.00, 0.99, 0.95,
                             0.88, 0.78, 0.65, 0.53, 0.40, 0.25};

// s_m(n) = A(n)·0.575·wm[r]·max(0, sin(r·0.81π/11 − 2.22e-4·n + π·[block 1 or 2])).
double Expected(int m, double n) {
  const int r = (m % 24) / 2, block = m / 24;
  const double s =
      std::sin(r * 0.81 * kPi / 11 - 2.22e-4 * n + (block == 1 || block == 2 ? kPi : 0));
  const double ramp = n < 2500 ? n / 2500 : 1.0;
  return ramp * 0.575 * kWeights[r] * std::max(0.0, s);
}

TEST(Muscles, SwimmingWavesFollowTheClosedForm) {
  for (double n : {0.0, 1.0, 1250.0, 2499.0, 3000.0, 40000.0, 1199999.0}) {
    const auto signal = MuscleSimulationSignal(n);
    for (int m = 0; m < kMuscleCount; ++m)
      EXPECT_NEAR(signal[m], Expected(m, n), 1e-6) << "muscle " << m << " call " << n;
  }
}

TEST(Muscles, FirstCallIsSilentAndTheRampIsHalfWayAtCall1250) {
  for (float s : MuscleSimulationSignal(0)) EXPECT_EQ(s, 0.0f);
  // Muscle 8 (row 4 of wave 1, phase 4·0.81π/11 − 0.2775 > 0) at half the ramp: 0.575·0.99·
  // sin(0.6478)·0.5 = 0.1718.
  const auto half = MuscleSimulationSignal(1250);
  EXPECT_NEAR(half[8],
              0.575 * 0.99 * std::sin(4 * 0.81 * kPi / 11 - 4 * 0.000015 * 3.7 * 1250) * 0.5, 1e-6);
  EXPECT_NEAR(half[8], 0.1718, 1e-4);
}

TEST(Muscles, EachRowDrivesTwoMusclesAndQuadrantsPairUp) {
  const auto s = MuscleSimulationSignal(30000);
  for (int m = 0; m < kMuscleCount; m += 2) EXPECT_EQ(s[m], s[m + 1]) << m;
  for (int m = 0; m < 24; ++m) {
    EXPECT_EQ(s[m], s[72 + m]);       // MDR and MDL share wave 1
    EXPECT_EQ(s[24 + m], s[48 + m]);  // MVR and MVL share wave 2
  }
}

TEST(Muscles, CrawlingWavesTakeOverAfterCall1200000) {
  const double n = 1500000;
  const auto s = MuscleSimulationSignal(n);
  for (int m = 0; m < 24; ++m) {
    const int r = m / 2;
    const double position = r == 11 ? 2.97 * kPi : r * (2.97 * kPi / 11);
    const double weight = r == 11 ? 0.6 : 1 + r * (-0.4 / 11);
    const double expected = std::max(0.0, std::sin(position - 4 * 0.000015 * 0.72 * n)) * weight;
    EXPECT_NEAR(s[m], expected, 1e-6) << m;
  }
}

TEST(Muscles, WormConfigurationsAreRecognisedByName) {
  EXPECT_TRUE(NamesAWorm("configuration/worm_alone_half_resolution"));
  EXPECT_TRUE(NamesAWorm("../shared/reference/worm_swim/configuration"));
  EXPECT_FALSE(NamesAWorm("../shared/reference/demo1/configuration"));
  EXPECT_FALSE(NamesAWorm("worms/demo1"));  // only the file's own name counts
}

}  // namespace
}  // namespace owval::engine
