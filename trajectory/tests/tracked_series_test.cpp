// Tracked series (tracked_series.hpp): read frame by frame or recorded a frame at a time, the
// series of a real reference file equals the whole trajectory's Track::Series bit for bit, and
// its frames pair as the trajectories' do.
#include "owval/trajectory/tracked_series.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "owval/base/errors.hpp"
#include "owval/testing/test_files.hpp"
#include "owval/trajectory/formats.hpp"

namespace owval {
namespace {
namespace fs = std::filesystem;

const fs::path kDemo1 = fs::path(OWVAL_SHARED_DIR) / "reference/demo1/position_buffer.txt";

// A particle and two group centroids (218 elastic, 125 liquid particles in demo1).
const std::vector<Track> kTracks = {
    {0, "", Axis::kY}, {0, "elastic", Axis::kY}, {0, "liquid", Axis::kX}, {0, "all", Axis::kZ}};

TEST(TrackedSeries, ReadFrameByFrameEqualsTheWholeTrajectorysSeries) {
  for (const fs::path& file : {testing::kBundledOneSprig, kDemo1}) {
    const Trajectory whole = ReadTrajectory(file);
    for (const Track& track : kTracks) {
      if (track.group == "liquid" && whole.count(ParticleKind::kLiquid) == 0) continue;
      const std::unique_ptr<FrameSource> frames = OpenFrameSource(file);
      const TrackedSeries streamed = ReadTrackedSeries(*frames, track);
      EXPECT_EQ(streamed.time_s, whole.time_s) << file << ", " << track.Describe();
      EXPECT_EQ(streamed.value, track.Series(whole)) << file << ", " << track.Describe();
      EXPECT_EQ(streamed.frame_count(), whole.frame_count());
    }
  }
}

TEST(TrackedSeries, RecorderGivenOneFrameAtATimeEqualsTheWholeTrajectorysSeries) {
  const Trajectory whole = ReadTrajectory(kDemo1);
  Trajectory header = whole;  // what an engine's FrameSink::Begin sees: no frames
  header.time_s.clear();
  header.positions.clear();
  for (const Track& track : kTracks) {
    TrackedSeriesRecorder recorder(header, track);
    for (std::size_t f = 0; f < whole.frame_count(); ++f)
      recorder.Add(whole.time_s[f], whole.position(f, 0));
    const TrackedSeries recorded = recorder.Take();
    EXPECT_EQ(recorded.time_s, whole.time_s) << track.Describe();
    EXPECT_EQ(recorded.value, track.Series(whole)) << track.Describe();
    const TrackedSeries of = TrackedSeriesOf(whole, track);
    EXPECT_EQ(of.value, recorded.value) << track.Describe();
  }
}

TEST(TrackedSeries, RecorderRefusesATrackThatNamesNothing) {
  const Trajectory whole = ReadTrajectory(testing::kBundledOneSprig);
  EXPECT_THROW(TrackedSeriesRecorder(whole, Track{whole.particle_count(), "", Axis::kY}),
               InputError);
  EXPECT_THROW(TrackedSeriesRecorder(whole, Track{0, "liquid", Axis::kY}), InputError);
}

// A reference at every frame against a candidate at every third frame, shifted by a thousandth of
// a frame (rounding of its time column): the series pair exactly as the trajectories do.
TEST(TrackedSeries, FramesPairAsTheTrajectoriesDo) {
  const Trajectory reference = ReadTrajectory(testing::kBundledOneSprig);
  Trajectory candidate = reference;
  candidate.time_s.clear();
  candidate.positions.clear();
  const double shift_s = 0.001 * (reference.time_s[1] - reference.time_s[0]);
  for (std::size_t f = 0; f < reference.frame_count(); f += 3)
    candidate.AppendFrame(reference.time_s[f] + shift_s, reference.position(f, 0));
  const Track track;
  const auto pairs =
      PairFramesByTime(TrackedSeriesOf(reference, track), TrackedSeriesOf(candidate, track));
  EXPECT_EQ(pairs, PairFramesByTime(reference, candidate));
  ASSERT_FALSE(pairs.empty());
  EXPECT_EQ(pairs[1], std::make_pair(std::size_t(3), std::size_t(1)));
}

// The pairing rule on frame times alone: frames meet to rounding (1% of the finer interval) or
// not at all; a frame a tenth of an interval off is a near miss, counted and not paired.
TEST(PairFramesByTime, PairsOnlyFramesAtTheSameTime) {
  const std::vector<double> reference = {0, 1, 2, 3, 4};
  std::size_t near_misses = 99;
  const auto exact = PairFramesByTime(reference, {0.004, 2, 4.009}, &near_misses);
  const std::vector<std::pair<std::size_t, std::size_t>> every_other = {{0, 0}, {2, 1}, {4, 2}};
  EXPECT_EQ(exact, every_other);
  EXPECT_EQ(near_misses, 0u);
  EXPECT_TRUE(PairFramesByTime(reference, {0.1, 1.1, 2.1, 3.1, 4.1}, &near_misses).empty());
  EXPECT_EQ(near_misses, 5u);
  EXPECT_EQ(PairFramesByTime(reference, {0.02, 1, 2.6}, &near_misses).size(), 1u);
  // 0.02 (2% of the finer 1 s) misses frame 0 and 2.6 misses frame 3 (0.4 off); frame 2, 0.6
  // off, has no frame of the other run within half an interval.
  EXPECT_EQ(near_misses, 2u);
}

}  // namespace
}  // namespace owval
