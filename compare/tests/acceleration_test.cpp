// The acceleration and boundary.fixed gates. acceleration: the moving particles' acceleration
// between paired frames
// (|x(t+dt) - 2x(t) + x(t-dt)| / dt^2), its median and upper quartile per kind averaged over the
// stencils, against the reference's. Sibernetic's demo1 with noise of 0.05-1 cu added to every
// moving particle in every frame, or replaced by its own moving average over 3-31 frames, passed
// every other gate (docs/checklist.md, "Attacks measured (round 7)"). boundary.fixed: the walls
// at every paired frame where the reference's are, to the printed precision.
#include <gtest/gtest.h>

#include <cmath>

#include "edited_runs.hpp"
#include "frame_acceleration.hpp"
#include "owval/compare/parity.hpp"
#include "owval/testing/reference_runs.hpp"

namespace owval::compare {
namespace {

using testing_edits::HonestDemo1Rerun;
using testing_edits::Jittered;
using testing_edits::MovingAverage;
using testing_edits::OneFrameDisplaced;
using testing_edits::ParticleAtRest;

// One liquid particle falling from rest at 9.8 cu/s^2 along -y, logged at `times_s`.
Trajectory FallingParticle(const std::vector<double>& times_s) {
  Trajectory t;
  t.box = {0, 10, 0, 10, 0, 10};
  t.type = {1.1f};
  for (double time : times_s) {
    const float x[3] = {5, float(9 - 4.9 * time * time), 5};
    t.AppendFrame(time, x);
  }
  return t;
}

TEST(FrameAcceleration, AStencilMeasuresTheAccelerationOfAFall) {
  const Trajectory t = FallingParticle({0, 0.1, 0.2, 0.3});
  internal::FrameAcceleration a({0});
  EXPECT_FALSE(a.Observe({t, 0}, 0.0));
  EXPECT_FALSE(a.Observe({t, 1}, 0.1));
  const auto s = a.Observe({t, 2}, 0.2);
  ASSERT_TRUE(s);
  EXPECT_NEAR(s->median, 9.8, 1e-4);  // float positions: 5e-7 cu in 0.01 s^2
  EXPECT_NEAR(s->upper_quartile, 9.8, 1e-4);
  EXPECT_DOUBLE_EQ(s->interval_s, 0.1);
}

TEST(FrameAcceleration, UnevenIntervalsMakeNoStencil) {
  const Trajectory t = FallingParticle({0, 0.1, 0.3, 0.4, 0.5});
  internal::FrameAcceleration a({0});
  EXPECT_FALSE(a.Observe({t, 0}, 0.0));
  EXPECT_FALSE(a.Observe({t, 1}, 0.1));
  EXPECT_FALSE(a.Observe({t, 2}, 0.3));  // 0.1 s then 0.2 s: velocity would leak into it
  EXPECT_FALSE(a.Observe({t, 3}, 0.4));
  EXPECT_TRUE(a.Observe({t, 4}, 0.5));
}

TEST(Acceleration, ARunAtRestIsJudgedAgainstThePrintedPrecision) {
  const Trajectory still = ParticleAtRest(5);
  Trajectory rounded = still;  // moved by the rounding of a 6-digit print (5e-6 of 5 cu)
  rounded.position(2, 0)[1] += 2.5e-5f;
  const ParityReport r = CompareTrajectories(still, rounded, {});
  const Gate& g = *r.gate("acceleration");
  EXPECT_EQ(g.status, GateStatus::kPass) << g.value << ": " << g.detail;
  EXPECT_TRUE(r.pass()) << r.FailedGates();
}

TEST(Acceleration, OneSprigAgainstItselfMeasuresZero) {
  const Trajectory& run = testing::BundledOneSprigRun();
  const ParityReport r = CompareTrajectories(run, run, {});
  const Gate& g = *r.gate("acceleration");
  EXPECT_EQ(g.value, 0.0);
  EXPECT_EQ(g.status, GateStatus::kPass);
  EXPECT_EQ(g.threshold.value, 0.25);  // the default
  EXPECT_NE(g.detail.find("elastic over 2498 stencils"), std::string::npos) << g.detail;
}

// Every wall moved 1 cu along x from frame 1 on, the moving particles left as they are.
Trajectory WallsMoved(const Trajectory& t) {
  Trajectory out = t;
  for (std::size_t f = 1; f < out.frame_count(); ++f)
    for (std::size_t p = 0; p < out.particle_count(); ++p)
      if (KindOf(out.type[p]) == ParticleKind::kBoundary) out.position(f, p)[0] += 1.0f;
  return out;
}

TEST(BoundaryFixed, OneSprigWithItsWallsAndAnchorMovedFailsOnlyThis) {
  const Trajectory& run = testing::BundledOneSprigRun();
  const ParityReport same = CompareTrajectories(run, run, {});
  EXPECT_EQ(same.gate("boundary.fixed")->value, 0.0);
  EXPECT_EQ(same.gate("boundary.fixed")->detail,
            "every boundary coordinate equal at every paired frame");
  const ParityReport moved = CompareTrajectories(run, WallsMoved(run), {});
  EXPECT_EQ(moved.FailedGates(), "boundary.fixed");  // boundary.worst_particle: 3% of the box
  const Gate& g = *moved.gate("boundary.fixed");
  EXPECT_GT(g.value, 1e3);
  EXPECT_NE(g.detail.find("at reference frame 1 "), std::string::npos) << g.detail;
}

TEST(BoundaryFixed, ASceneWithoutWallsIsNotApplicable) {
  const Trajectory t = FallingParticle({0, 0.1, 0.2});
  // A copy: the report is a temporary.
  const Gate g = *CompareTrajectories(t, t, {}).gate("boundary.fixed");
  EXPECT_EQ(g.status, GateStatus::kNotApplicable);
}

ParityReport Demo1Edited(const Trajectory& candidate) {
  return CompareTrajectories(*testing::SiberneticDemo1Run(), candidate, {});
}

TEST(AccelerationParity, Demo1AgainstItselfMeasuresZero) {
  OWVAL_REQUIRE_DEMO1();
  const ParityReport r = Demo1Edited(*testing::SiberneticDemo1Run());
  const Gate& g = *r.gate("acceleration");
  EXPECT_EQ(g.value, 0.0);
  EXPECT_NE(g.detail.find("elastic over 498 stencils"), std::string::npos) << g.detail;
  EXPECT_NE(g.detail.find("liquid over 498 stencils"), std::string::npos) << g.detail;
  EXPECT_TRUE(r.pass()) << r.FailedGates();
}

TEST(AccelerationParity, Demo1WithNoiseOnEveryFrameFailsOnlyThis) {
  OWVAL_REQUIRE_DEMO1();
  const Trajectory& demo1 = *testing::SiberneticDemo1Run();
  // 0.05 cu, a thirtieth of r0: every motion gate admits it.
  const ParityReport r = Demo1Edited(Jittered(demo1, 0.05, 1));
  EXPECT_EQ(r.FailedGates(), "acceleration");
  const Gate& g = *r.gate("acceleration");
  // The elastic median +86% (5.40e5 cu/s^2, 4.0 m/s^2, in the reference).
  EXPECT_NEAR(g.value, 0.861, 0.01) << g.detail;
}

TEST(AccelerationParity, Demo1SmoothedOverThreeFramesFailsOnlyThis) {
  OWVAL_REQUIRE_DEMO1();
  const Trajectory& demo1 = *testing::SiberneticDemo1Run();
  const ParityReport r = Demo1Edited(MovingAverage(demo1, 3, 1));
  EXPECT_EQ(r.FailedGates(), "acceleration");
  const Gate& g = *r.gate("acceleration");
  EXPECT_NEAR(g.value, 0.644, 0.01) << g.detail;  // the liquid's upper quartile -64%
}

TEST(AccelerationParity, AnHonestPerturbedRerunPassesAndTheSameWithNoiseFails) {
  OWVAL_REQUIRE_DEMO1();
  const Trajectory rerun = HonestDemo1Rerun(0.05);  // 125 frames
  const Gate honest = *Demo1Edited(rerun).gate("acceleration");
  EXPECT_EQ(honest.status, GateStatus::kPass) << honest.value << ": " << honest.detail;
  EXPECT_GT(honest.value, 1e-3);  // diverged: not the reference's own frames
  const Gate noisy = *Demo1Edited(Jittered(rerun, 0.05, 1)).gate("acceleration");
  EXPECT_EQ(noisy.status, GateStatus::kFail) << noisy.value << ": " << noisy.detail;
}

// acceleration.worst_stencil: one frame of demo1 written with the liquid (or the elastic body)
// 1 r0 (1.67 cu) aside, the frames around it untouched. Every motion gate admits it (the worst
// particle 1.9% of the box) and the run's averages dilute it (`acceleration` 0.055 / 0.153),
// but the stencils around the frame spike.
TEST(AccelerationParity, Demo1WithOneFrameDisplacedFailsOnlyTheWorstStencil) {
  OWVAL_REQUIRE_DEMO1();
  const Trajectory& demo1 = *testing::SiberneticDemo1Run();
  const ParityReport liquid =
      Demo1Edited(OneFrameDisplaced(demo1, ParticleKind::kLiquid, 250, 1.67f));
  EXPECT_EQ(liquid.FailedGates(), "acceleration.worst_stencil");
  const Gate& g = *liquid.gate("acceleration.worst_stencil");
  EXPECT_NEAR(g.value, 13.85, 0.05) << g.detail;
  EXPECT_NE(g.detail.find("liquid: 13.9 at the stencil around reference frame 250"),
            std::string::npos)
      << g.detail;
  const ParityReport elastic =
      Demo1Edited(OneFrameDisplaced(demo1, ParticleKind::kElastic, 250, 1.67f));
  EXPECT_EQ(elastic.FailedGates(), "acceleration.worst_stencil");
  EXPECT_NEAR(elastic.gate("acceleration.worst_stencil")->value, 38.0, 0.1);
}

TEST(AccelerationParity, TheWorstStencilOfAnHonestRerunPasses) {
  OWVAL_REQUIRE_DEMO1();
  const Gate same = *Demo1Edited(*testing::SiberneticDemo1Run()).gate("acceleration.worst_stencil");
  EXPECT_EQ(same.value, 0.0) << same.detail;
  // Its impacts fall a frame or two from the reference's: within the window, not a spike.
  const Gate honest = *Demo1Edited(HonestDemo1Rerun(0.05)).gate("acceleration.worst_stencil");
  EXPECT_EQ(honest.status, GateStatus::kPass) << honest.value << ": " << honest.detail;
  EXPECT_GT(honest.value, 0.01) << honest.detail;  // diverged: not the reference's own frames
}

// One particle's acceleration passes through zero twice a period: measured against the run's
// mean, one_sprig's own run measures 0, and one frame kicked 0.2 cu (a seventh of its amplitude)
// fails (6.95; frames.position fails too): a jump d makes 2d/dt^2 at a 20 us stencil.
TEST(Acceleration, OneSprigWithOneFrameKickedFailsTheWorstStencil) {
  const Trajectory& run = testing::BundledOneSprigRun();
  EXPECT_EQ(CompareTrajectories(run, run, {}).gate("acceleration.worst_stencil")->value, 0.0);
  const ParityReport kicked =
      CompareTrajectories(run, OneFrameDisplaced(run, ParticleKind::kElastic, 1250, 0.2f), {});
  const Gate& g = *kicked.gate("acceleration.worst_stencil");
  EXPECT_EQ(g.status, GateStatus::kFail) << g.value << ": " << g.detail;
}

}  // namespace
}  // namespace owval::compare
