// The frames.position gate: the tracked particle's whole position against the frame gate's scale
// and threshold. The frames gate reads one coordinate, so a tracked particle that also moved
// along another axis (one_sprig's vertical oscillator swinging sideways) passed every gate.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "owval/compare/parity.hpp"
#include "owval/testing/reference_runs.hpp"
#include "owval/trajectory/formats.hpp"

namespace owval::compare {
namespace {

// Particle 0 moved along x by `offset_cu` (its y, the tracked coordinate, kept), the offset
// growing evenly over frames 1-100 and held after: a step at frame 1 would be a jump of 0.34 cu
// in 20 us, which acceleration.worst_stencil fails by itself.
Trajectory SwungSideways(double offset_cu) {
  Trajectory t = testing::BundledOneSprigRun();
  for (std::size_t f = 1; f < t.frame_count(); ++f)
    t.position(f, 0)[0] += float(offset_cu * std::min(1.0, double(f) / 100));
  return t;
}

TEST(FramesPosition, ReferenceAgainstItselfIsZero) {
  const ParityReport r =
      CompareTrajectories(testing::BundledOneSprigRun(), testing::BundledOneSprigRun(), {});
  ASSERT_NE(r.gate("frames.position"), nullptr);
  EXPECT_EQ(r.gate("frames.position")->value, 0.0);
  EXPECT_TRUE(r.pass());
}

TEST(FramesPosition, ATrackedParticleOffItsAxisFails) {
  // 0.34 cu sideways: 10% of the 3.388 cu range of its y, 1% of the box.
  const ParityReport r =
      CompareTrajectories(testing::BundledOneSprigRun(), SwungSideways(0.34), {});
  EXPECT_EQ(r.FailedGates(), "frames.position");
  EXPECT_NEAR(r.gate("frames.position")->value, 0.34 / 3.388, 1e-3);
  EXPECT_EQ(r.gate("frames")->value, 0.0);
  EXPECT_NE(r.gate("frames.position")->detail.find("(+0.34, +0, +0) cu"), std::string::npos)
      << r.gate("frames.position")->detail;
}

TEST(FramesPosition, WithinTheFrameThresholdPasses) {
  const ParityReport r =
      CompareTrajectories(testing::BundledOneSprigRun(), SwungSideways(0.1), {});  // 3%
  EXPECT_TRUE(r.pass()) << r.FailedGates();
  EXPECT_NEAR(r.gate("frames.position")->value, 0.1 / 3.388, 1e-3);
}

}  // namespace
}  // namespace owval::compare
