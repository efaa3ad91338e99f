#include "owval/kinematics/body_shape.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "owval/base/errors.hpp"
#include "owval/kinematics/midline.hpp"

namespace owval::kinematics {
namespace {

// A straight worm along z: rings of 8 particles of radius 1.5 cu around (10, 5, z), one ring per
// midline bin 51..149 at z = 2 + 0.5 * (bin - 51), so span 98 * 0.5 = 49 cu and diameter 3 cu.
Trajectory StraightWorm(float lift_cu) {
  Trajectory t;
  t.box = {0, 40, 0, 40, 0, 60};
  t.time_step_s = 2e-5;
  std::vector<float> frame;
  for (int bin = 51; bin < 51 + kMidlineBins; ++bin) {
    const float type = 2.1f + float(bin - 1) * 1e-4f + 2e-5f;
    for (int k = 0; k < 8; ++k) {
      const double angle = 2 * M_PI * k / 8;
      t.type.push_back(type);
      frame.insert(frame.end(),
                   {10 + 1.5f * float(std::cos(angle)), 5 + lift_cu + 1.5f * float(std::sin(angle)),
                    2 + 0.5f * float(bin - 51)});
    }
  }
  t.AppendFrame(0, frame.data());
  return t;
}

TEST(BodyShape, StraightWormHasItsRingsDiameterAndLength) {
  const Trajectory worm = StraightWorm(0);
  ASSERT_TRUE(IsWorm(worm));
  const BodyShape s = MeasureBodyShape(worm, 0);
  EXPECT_NEAR(s.span_cu, 49.0, 1e-4);
  EXPECT_NEAR(s.cross_section_diameter_cu, 3.0, 1e-5);
  for (double ring_cu : s.ring_diameter_cu) EXPECT_NEAR(ring_cu, 3.0, 1e-5);
  EXPECT_NEAR(s.centre_of_mass_cu[0], 10.0, 1e-5);
  EXPECT_NEAR(s.centre_of_mass_cu[1], 5.0, 1e-5);
  EXPECT_NEAR(s.centre_of_mass_cu[2], 2 + 0.5 * 49, 1e-4);
  EXPECT_NEAR(MeasureBodyShape(StraightWorm(2.5f), 0).centre_of_mass_cu[1], 7.5, 1e-5);
}

TEST(BodyShape, RefusesATrajectoryWithoutAWorm) {
  Trajectory t;
  t.box = {0, 1, 0, 1, 0, 1};
  t.type = {2.1f};
  const float p[3] = {0.5f, 0.5f, 0.5f};
  t.AppendFrame(0, p);
  EXPECT_THROW(MeasureBodyShape(t, 0), InputError);
}

}  // namespace
}  // namespace owval::kinematics
