#include "owval/compare/parity.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "owval/base/errors.hpp"
#include "owval/compare/stability.hpp"
#include "owval/trajectory/formats.hpp"

namespace owval::compare {
namespace {

const Trajectory& OneSprig() {
  static const Trajectory t =
      ReadTrajectory(std::filesystem::path(OWVAL_SOURCE_DIR) /
                     "reference_trajectories/one_sprig/position_buffer.txt");
  return t;
}

TEST(Parity, ReferenceAgainstItselfPassesWithZeroError) {
  const ParityReport r = CompareTrajectories(OneSprig(), OneSprig(), {});
  EXPECT_TRUE(r.pass());
  EXPECT_EQ(r.paired_frames, 2500u);
  EXPECT_EQ(r.l2_mean_cu, 0.0);
  for (const FrameParity& f : r.frames) EXPECT_EQ(f.relative_difference, 0.0);
  EXPECT_EQ(*r.period_gap, 0.0);
}

TEST(Parity, ElasticYScaledBy106FailsTheFrameGateAndNamesFrames) {
  Trajectory scaled = OneSprig();
  for (std::size_t f = 0; f < scaled.frame_count(); ++f) scaled.position(f, 0)[1] *= 1.06f;
  ParityOptions options;
  options.sample_frames = {0, 15, 100, 200};
  const ParityReport r = CompareTrajectories(OneSprig(), scaled, options);
  EXPECT_FALSE(r.frames_pass);
  EXPECT_FALSE(r.pass());
  EXPECT_EQ(r.failing_frames, (std::vector<std::size_t>{0, 15, 100, 200}));
  // 6% of y ≈ 18 is ≈ 1.1 cu against a 3.39 cu range: about a third of the scale.
  EXPECT_NEAR(r.frames[0].relative_difference, 0.06 * 20.04 / 3.388, 1e-3);
  EXPECT_NE(r.ToMarkdown().find("failing frames | 0, 15, 100, 200"), std::string::npos);
}

TEST(Parity, PairsFramesByTimeAcrossLogSteps) {
  Trajectory coarse = OneSprig();
  // Keep every 10th frame: a candidate logged with log step 10.
  Trajectory thinned;
  thinned.box = coarse.box;
  thinned.type = coarse.type;
  thinned.time_step_s = coarse.time_step_s;
  thinned.log_step = 10;
  for (std::size_t f = 0; f < coarse.frame_count(); f += 10)
    thinned.AppendFrame(coarse.time_s[f], coarse.position(f, 0));
  const auto pairs = PairFramesByTime(coarse, thinned);
  ASSERT_EQ(pairs.size(), 250u);
  EXPECT_EQ(pairs[3], (std::pair<std::size_t, std::size_t>{30, 3}));
  EXPECT_TRUE(CompareTrajectories(coarse, thinned, {}).frames_pass);
}

TEST(Parity, RefusesDifferentParticleCounts) {
  Trajectory fewer = OneSprig();
  fewer.type.pop_back();
  Trajectory rebuilt;
  rebuilt.type = fewer.type;
  rebuilt.box = fewer.box;
  std::vector<float> frame(fewer.type.size() * 3, 1.0f);
  rebuilt.AppendFrame(0, frame.data());
  EXPECT_THROW(CompareTrajectories(OneSprig(), rebuilt, {}), InputError);
}

Trajectory TwoLiquidParticles(std::size_t frames) {
  Trajectory t;
  t.box = {0, 10, 0, 10, 0, 10};
  t.time_step_s = 1e-3;
  t.type = {1.1f, 1.1f};
  for (std::size_t f = 0; f < frames; ++f) {
    const float x[6] = {5, 5, 5, 6, 5, 5};
    t.AppendFrame(double(f) * 1e-3, x);
  }
  t.velocities.assign(frames * 6, 0.0f);
  t.density.assign(frames * 2, 1000.0f);
  return t;
}

TEST(Stability, CleanTrajectoryPasses) {
  EXPECT_TRUE(CheckStability(TwoLiquidParticles(5)).pass());
}

TEST(Stability, FindsNaNEscapesBlowUpAndDensityWithFirstFrames) {
  Trajectory t = TwoLiquidParticles(10);
  t.position(3, 0)[1] = std::numeric_limits<float>::quiet_NaN();
  t.position(5, 1)[0] = 12.5f;  // 2.5 cu outside, tolerance 1
  t.velocities[(7 * 2 + 0) * 3] = 50.0f;
  t.velocities[(7 * 2 + 1) * 3] = 50.0f;
  t.density[8 * 2 + 1] = 9000.0f;
  const StabilityReport r = CheckStability(t);
  EXPECT_FALSE(r.pass());
  EXPECT_EQ(r.non_finite.count, 1u);
  EXPECT_EQ(*r.non_finite.first_frame, 3u);
  EXPECT_EQ(r.outside_box.count, 1u);
  EXPECT_EQ(*r.outside_box.first_frame, 5u);
  EXPECT_EQ(r.blow_up.count, 1u);
  EXPECT_EQ(*r.blow_up.first_frame, 7u);
  EXPECT_EQ(*r.density_out_of_range.first_frame, 8u);
}

TEST(Stability, BlowUpFromPositionsWhenNoVelocities) {
  Trajectory t = TwoLiquidParticles(4);
  t.velocities.clear();
  t.position(2, 0)[0] = 9.9f;  // 4.9 cu in 1 ms = 0.036 m/s: fine
  EXPECT_TRUE(CheckStability(t).pass());
  StabilityOptions strict;
  strict.speed_limit_m_s = 0.01;
  EXPECT_EQ(CheckStability(t, strict).blow_up.first_frame, 2u);
}

TEST(Incompressibility, MeasuresMeanAndMaxDeviation) {
  Trajectory t = TwoLiquidParticles(3);
  t.density = {1000, 1000, 1000, 1030, 1000, 1000};  // frame 1 particle 1 is 3% dense
  const IncompressibilityReport r = CheckIncompressibility(t);
  EXPECT_NEAR(r.max_deviation, 0.03, 1e-6);
  EXPECT_NEAR(r.mean_deviation, 0.0075, 1e-6);  // 0.03 over 4 particle-frames (frame 0 skipped)
  EXPECT_EQ(*r.worst_frame, 1u);
  EXPECT_FALSE(r.pass());
  t.density[3] = 1005;
  EXPECT_TRUE(CheckIncompressibility(t).pass());
}

TEST(Incompressibility, RefusesTrajectoryWithoutDensity) {
  EXPECT_THROW(CheckIncompressibility(OneSprig()), InputError);
}

}  // namespace
}  // namespace owval::compare
