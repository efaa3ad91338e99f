// Frames are compared only where their times meet, and a sparse pairing of an oscillating
// reference fails: a candidate whose header claims another time step was compared at the wrong
// instants and passed (one_sprig at k = 3.3e8 with the time step 2e-5 s written as 2.09789e-5 s,
// checklist ready, exit 0).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>

#include "owval/compare/parity.hpp"
#include "owval/testing/reference_runs.hpp"
#include "owval/trajectory/formats.hpp"

namespace owval::compare {
namespace {

// one_sprig's spring as a stiffer one would move it: the reference's sine (equilibrium 18.3523,
// half-amplitude 1.694, from its maximum) with the period of k = 3.3e8 (0.6908 ms, 4.7% short),
// at the reference's steps, and frame times claiming a time step `claimed_dt_s`.
Trajectory StifferSpring(double claimed_dt_s) {
  Trajectory t = testing::BundledOneSprigRun();
  const double dt = t.time_step_s, period_s = 0.6908024e-3;
  for (std::size_t f = 0; f < t.frame_count(); ++f) {
    const double y = 18.352341 + 1.694013 * std::cos(2 * std::numbers::pi * f * dt / period_s);
    t.position(f, 0)[1] = float(y);
    t.time_s[f] = f * claimed_dt_s;
  }
  t.time_step_s = claimed_dt_s;
  return t;
}

TEST(TimeBase, AStifferSpringFailsOnItsOwnTimeBase) {
  const ParityReport r =
      CompareTrajectories(testing::BundledOneSprigRun(), StifferSpring(2e-5), {});
  EXPECT_FALSE(r.pass());
  EXPECT_EQ(r.gate("period")->status, GateStatus::kFail);
}

TEST(TimeBase, AStifferSpringWithAStretchedTimeStepFails) {
  // 2e-5 s × 0.7246109 / 0.6908024: the stiffer spring's period looks like the reference's.
  const ParityReport r =
      CompareTrajectories(testing::BundledOneSprigRun(), StifferSpring(2.09789e-5), {});
  EXPECT_FALSE(r.pass()) << r.ToTable();
  EXPECT_GT(r.misaligned_pairs, 2000u);  // they met within half a frame, at other times
  EXPECT_EQ(r.gate("sampling.oscillation")->status, GateStatus::kFail) << r.ToTable();
}

TEST(TimeBase, ACandidateLoggedEveryTenthStepStillPasses) {
  Trajectory thinned;
  const Trajectory& ref = testing::BundledOneSprigRun();
  thinned.box = ref.box, thinned.type = ref.type;
  thinned.time_step_s = ref.time_step_s, thinned.log_step = 10;
  for (std::size_t f = 0; f < ref.frame_count(); f += 10)
    thinned.AppendFrame(ref.time_s[f], ref.position(f, 0));
  const ParityReport r = CompareTrajectories(ref, thinned, {});
  EXPECT_TRUE(r.pass()) << r.ToTable();
  EXPECT_EQ(r.misaligned_pairs, 0u);
  // 10 steps (0.2 ms) of a 0.7246 ms period.
  EXPECT_NEAR(r.gate("sampling.oscillation")->value, 2e-4 / 0.7246e-3, 2e-3);
}

TEST(TimeBase, SamplingTooSparseForTheOscillationFails) {
  // Every 20th step (0.4 ms, more than half the 0.7246 ms period): aliased, not resolved.
  Trajectory sparse;
  const Trajectory& ref = testing::BundledOneSprigRun();
  sparse.box = ref.box, sparse.type = ref.type;
  sparse.time_step_s = ref.time_step_s, sparse.log_step = 20;
  for (std::size_t f = 0; f < ref.frame_count(); f += 20)
    sparse.AppendFrame(ref.time_s[f], ref.position(f, 0));
  const ParityReport r = CompareTrajectories(ref, sparse, {});
  EXPECT_EQ(r.gate("sampling.oscillation")->status, GateStatus::kFail) << r.ToTable();
  EXPECT_EQ(r.gate("sampling")->status, GateStatus::kPass);  // 0.8% of the duration
}

TEST(TimeBase, ANonOscillatingReferenceLeavesTheGateNotApplicable) {
  Trajectory still = testing::BundledOneSprigRun();
  for (std::size_t f = 0; f < still.frame_count(); ++f) still.position(f, 0)[1] = 18.35f;
  const ParityReport r = CompareTrajectories(still, still, {});
  EXPECT_EQ(r.gate("sampling.oscillation")->status, GateStatus::kNotApplicable);
}

}  // namespace
}  // namespace owval::compare

namespace owval::compare {
namespace {

// The stiffer spring's own frames, each relabelled with the reference frame time nearest its
// stretched time (an HDF5 /time column can say anything): dense, aligned, in phase.
TEST(TimeBase, AStifferSpringRelabelledFrameByFrameFails) {
  const Trajectory& ref = testing::BundledOneSprigRun();
  Trajectory warped = StifferSpring(2e-5);
  const double stretch = 0.7246109 / 0.6908024;
  Trajectory out;
  out.box = ref.box, out.type = ref.type, out.time_step_s = ref.time_step_s;
  for (std::size_t j = 0; j < warped.frame_count(); ++j) {
    const std::size_t k = std::size_t(std::lround(double(j) * stretch));
    if (k >= ref.frame_count()) break;
    out.AppendFrame(ref.time_s[k], warped.position(j, 0));
  }
  const ParityReport r = CompareTrajectories(ref, out, {});
  EXPECT_FALSE(r.pass()) << r.ToTable();
  // Intervals of one and two steps about a mean of 1.05: the time column is not a time base.
  EXPECT_EQ(r.gate("time_base")->status, GateStatus::kFail);
  EXPECT_NEAR(r.gate("time_base")->value, 2 / stretch - 1, 1e-3) << r.ToTable();
}

TEST(TimeBase, EvenlySpacedCandidatesPassTheTimeBaseGate) {
  EXPECT_LT(CompareTrajectories(testing::BundledOneSprigRun(), testing::BundledOneSprigRun(), {})
                .gate("time_base")
                ->value,
            1e-9);
  const ParityReport r =
      CompareTrajectories(testing::BundledOneSprigRun(), StifferSpring(2.09789e-5), {});
  EXPECT_EQ(r.gate("time_base")->status, GateStatus::kPass);
}

}  // namespace
}  // namespace owval::compare
