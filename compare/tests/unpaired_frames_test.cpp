// The unpaired_frames gate and its measures (unpaired_frames.hpp): a candidate logged more finely
// than the reference has frames between the pairs that no other gate reads; each is held to the
// reference's fastest reach over the interval.
#include "unpaired_frames.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "edited_runs.hpp"
#include "owval/compare/parity.hpp"
#include "owval/testing/reference_runs.hpp"

namespace owval::compare {
namespace {

// One liquid particle moving along x at `speed_cu_s`, `frames` frames 1 ms apart.
Trajectory Moving(double speed_cu_s, int frames) {
  Trajectory t;
  t.box = {0, 100, 0, 100, 0, 100};
  t.type = {1.1f};
  for (int f = 0; f < frames; ++f) {
    const float x[3] = {float(10 + speed_cu_s * f * 1e-3), 50, 50};
    t.AppendFrame(f * 1e-3, x);
  }
  return t;
}

TEST(PeakSpeedMeasure, IsTheFastestChordAndWhere) {
  Trajectory t = Moving(1000, 5);  // 1 cu a frame
  t.position(3, 0)[1] += 4;        // 4 cu aside at frame 3: sqrt(17) cu from frame 2
  internal::PeakSpeed s({0});
  for (std::size_t f = 0; f < t.frame_count(); ++f) s.Observe({t, f}, f, t.time_s[f]);
  EXPECT_NEAR(s.speed_cu_s(), std::sqrt(17.0) * 1e3, 1e-2);
  EXPECT_EQ(s.from_frame(), 2u);
  EXPECT_EQ(s.to_frame(), 3u);
  EXPECT_EQ(s.intervals(), 4u);
  EXPECT_NEAR(s.duration_s(), 4e-3, 1e-12);
}

TEST(PeakSpeedMeasure, AFrameAtTheSameTimeIsNoIntervalAndANaNIsTheFastest) {
  const Trajectory t = Moving(1000, 3);
  internal::PeakSpeed s({0});
  s.Observe({t, 0}, 0, 0.0);
  s.Observe({t, 1}, 1, 0.0);  // no time between: not measured, not divided by zero
  EXPECT_EQ(s.intervals(), 0u);
  EXPECT_EQ(s.speed_cu_s(), 0.0);
  Trajectory nan = t;
  nan.position(2, 0)[0] = std::numeric_limits<float>::quiet_NaN();
  s.Observe({nan, 2}, 2, 1e-3);
  EXPECT_EQ(s.speed_cu_s(), INFINITY);
}

TEST(ExcursionsMeasure, IsTheFarthestStrayOutsideThePairsBox) {
  Trajectory t = Moving(1000, 5);  // pairs at frames 0 and 4, 1 cu a frame along x
  t.position(2, 0)[1] += 3;        // 3 cu aside at frame 2
  t.position(3, 0)[0] += 3;        // 3 cu ahead at frame 3: 2 cu past the pair at frame 4
  internal::Excursions e({0});
  e.ObservePaired({t, 0}, 0, t.time_s[0]);
  for (std::size_t f = 1; f < 4; ++f) e.ObserveUnpaired({t, f});
  e.ObservePaired({t, 4}, 4, t.time_s[4]);
  EXPECT_NEAR(e.excursion_cu(), 3, 1e-5);  // the largest axis's excess
  EXPECT_NEAR(e.speed_cu_s(), 3 / 4e-3, 1e-2);
  EXPECT_EQ(e.from_frame(), 0u);
  EXPECT_EQ(e.to_frame(), 4u);
  EXPECT_EQ(e.unpaired_frames(), 3u);
  Trajectory nan = Moving(1000, 3);
  nan.position(1, 0)[2] = std::numeric_limits<float>::quiet_NaN();
  internal::Excursions n({0});
  n.ObservePaired({nan, 0}, 0, 0.0);
  n.ObserveUnpaired({nan, 1});
  n.ObservePaired({nan, 2}, 2, 2e-3);
  EXPECT_EQ(n.speed_cu_s(), INFINITY);
}

// one_sprig logged every step against itself logged every 5 steps: an honest finer candidate
// strays no farther than its spring swings; the same with one unpaired frame's particle written
// 5 cu aside (three half-amplitudes) fails this gate and no other, since no other reads that
// frame. Logged as the reference is, there is nothing between the pairs to read.
TEST(UnpairedFrames, AFinerCandidatesFrameWrittenAsideFailsOnlyThis) {
  const Trajectory& run = testing::BundledOneSprigRun();
  const Trajectory coarse = testing_edits::EveryNthFrame(run, 5);
  const ParityReport honest = CompareTrajectories(coarse, run, {});
  const Gate& h = *honest.gate("unpaired_frames");
  EXPECT_EQ(h.status, GateStatus::kPass) << h.detail;
  EXPECT_LT(h.value, 0.2) << h.detail;  // 0.105: the spring turns within 5 steps, 0.15 cu out
  EXPECT_TRUE(honest.pass()) << honest.FailedGates();
  Trajectory aside = run;
  aside.position(1252, 0)[0] += 5;  // between the pairs at frames 1250 and 1255
  const ParityReport r = CompareTrajectories(coarse, aside, {});
  EXPECT_EQ(r.FailedGates(), "unpaired_frames");
  EXPECT_NE(r.gate("unpaired_frames")->detail.find("paired frames 1250 and 1255"),
            std::string::npos)
      << r.gate("unpaired_frames")->detail;
  const Gate same = *CompareTrajectories(run, run, {}).gate("unpaired_frames");
  EXPECT_EQ(same.status, GateStatus::kNotApplicable) << same.detail;
  EXPECT_NE(same.detail.find("no frames between its paired ones"), std::string::npos);
}

TEST(UnpairedFrames, ASceneAtRestIsJudgedAgainstThePrintedPrecision) {
  const Trajectory still = Moving(0, 9);
  const Trajectory coarse = testing_edits::EveryNthFrame(still, 4);
  Trajectory rounded = still;  // moved by less than a print's rounding
  rounded.position(2, 0)[0] += 1e-4f;
  const Gate g = *CompareTrajectories(coarse, rounded, {}).gate("unpaired_frames");
  EXPECT_EQ(g.status, GateStatus::kPass) << g.detail;
  Trajectory jumped = still;
  jumped.position(2, 0)[0] += 1.0f;  // 1% of the box at one frame, where nothing moves
  EXPECT_EQ(CompareTrajectories(coarse, jumped, {}).gate("unpaired_frames")->status,
            GateStatus::kFail);
}

}  // namespace
}  // namespace owval::compare
