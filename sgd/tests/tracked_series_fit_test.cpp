// What a fit keeps of a run or a reference is its tracked series (trajectory/tracked_series.hpp):
// on real runs and reference files, the series, the residuals and the analytic fit's loss equal
// what the whole trajectories gave, bit for bit.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>

#include "owval/base/errors.hpp"
#include "owval/compare/signal_metrics.hpp"
#include "owval/engine/config.hpp"
#include "owval/engine/run.hpp"
#include "owval/sgd/engine_simulator.hpp"
#include "owval/sgd/gradient_fit.hpp"
#include "owval/sgd/targets.hpp"
#include "owval/testing/scratch_directory.hpp"
#include "owval/testing/test_files.hpp"
#include "owval/trajectory/formats.hpp"

namespace owval::sgd {
namespace {
namespace fs = std::filesystem;

const fs::path kReference = fs::path(OWVAL_SHARED_DIR) / "reference";
const fs::path kOneSprigRun = owval::testing::kBundledOneSprig;

// 0.01 s of one_sprig (500 steps, a frame every 2: the particle crosses its equilibrium 27
// times), one thread, positions only: what EngineSimulator runs.
engine::RunOptions ShortRun() {
  engine::RunOptions o;
  o.duration_s = 0.01;
  o.log_step = 2;
  o.threads = 1;
  o.record_fields = false;
  return o;
}

engine::SiberneticConfig OneSprig() {
  return engine::ReadSiberneticConfig(kReference / "one_sprig/configuration");
}

TEST(EngineSimulator, RunTrackedSeriesEqualsTheWholeRunsSeries) {
  const engine::SiberneticConfig config = OneSprig();
  const Trajectory whole = engine::Run(config, ShortRun());
  ASSERT_GT(whole.frame_count(), 100u);
  for (const Track& track : {Track{0, "", Axis::kY}, Track{0, "elastic", Axis::kX}}) {
    const TrackedSeries streamed = RunTrackedSeries(config, ShortRun(), track);
    EXPECT_EQ(streamed.time_s, whole.time_s) << track.Describe();
    EXPECT_EQ(streamed.value, track.Series(whole)) << track.Describe();
  }
  EXPECT_THROW(RunTrackedSeries(config, ShortRun(), Track{whole.particle_count(), "", Axis::kY}),
               InputError);
}

// period, half_amplitude and rms against the bundled one_sprig run: the residuals of the
// streamed run and the streamed reference equal the whole trajectories' (the formulas targets.hpp
// states, on Track::Series and PairFramesByTime of the trajectories).
TEST(Targets, ResidualsOfTrackedSeriesEqualTheWholeTrajectories) {
  const engine::SiberneticConfig config = OneSprig();
  const std::vector<Parameter> parameters = {{"elasticity_coefficient", 2.9e8, true}};
  const Track track;  // particle 0 y
  const std::vector<Target> targets = {ParseTarget("period=0.7246e-3:scale=0.725e-3"),
                                       ParseTarget("half_amplitude=1.694:scale=1.694:weight=0.25"),
                                       ParseTarget("rms=0:scale=2:ref=" + kOneSprigRun.string())};
  const Objective objective =
      MakeObjective(EngineSimulator(config, ShortRun(), parameters), track, targets);
  const std::vector<double> residuals = objective({2.9e8});

  engine::RunOptions options = ShortRun();
  options.constants.elasticity_coefficient = 2.9e8;
  const Trajectory run = engine::Run(config, options);
  const Trajectory reference = ReadTrajectory(kOneSprigRun);
  const std::vector<double> series = track.Series(run), reference_series = track.Series(reference);
  const compare::SignalMetrics m = compare::MeasureSignal(run.time_s, series);
  ASSERT_TRUE(m.period_s && m.half_amplitude);
  double sum = 0;
  const auto pairs = PairFramesByTime(reference, run);
  ASSERT_GT(pairs.size(), 100u);
  for (const auto& [fr, fc] : pairs)
    sum += (series[fc] - reference_series[fr]) * (series[fc] - reference_series[fr]);
  const std::vector<double> expected = {(*m.period_s - 0.7246e-3) / 0.725e-3,
                                        std::sqrt(0.25) * (*m.half_amplitude - 1.694) / 1.694,
                                        std::sqrt(sum / double(pairs.size())) / 2};
  EXPECT_EQ(residuals, expected);
  EXPECT_GT(std::abs(expected[2]), 1e-3);  // the runs differ: rms measures something
}

// An external command (cp) writes the trajectory: its series is the file's.
TEST(CommandSimulator, KeepsTheTrackedSeriesOfTheFileTheCommandWrote) {
  const fs::path work = owval::testing::TestScratch() / "cmdsim";
  const Simulator simulate = CommandSimulator(
      "cp " + kOneSprigRun.string() + " {out}/position_buffer.txt # {k}", {{"k", 1, false}}, work);
  const Track track{0, "elastic", Axis::kY};
  const TrackedSeries series = simulate({1}, track);
  const Trajectory whole = ReadTrajectory(kOneSprigRun);
  EXPECT_EQ(series.time_s, whole.time_s);
  EXPECT_EQ(series.value, track.Series(whole));
  fs::remove_all(work);
}

// The analytic fit's loss from a reference read frame by frame: each frame's target is the
// group centroid of the whole trajectory's frame (trajectory.hpp's Centroid), up to `steps`.
TEST(TrackLoss, StreamedReferenceGivesTheWholeTrajectorysCentroids) {
  const fs::path file = kReference / "demo1/position_buffer.txt";
  const Trajectory whole = ReadTrajectory(file);
  const std::size_t steps = 2000;  // 100 frames at log step 20
  const std::unique_ptr<FrameSource> frames = OpenFrameSource(file);
  const auto loss = GroupCentroidLoss(*frames, {"elastic", "liquid"}, steps, 88.844);
  ASSERT_EQ(loss.size(), 2u);
  for (std::size_t g = 0; g < 2; ++g) {
    const std::vector<std::size_t> members = GroupIndices(whole, g == 0 ? "elastic" : "liquid");
    const engine::LossTerm& term = loss[g];
    ASSERT_EQ(term.frame_steps.size(), 100u);
    EXPECT_EQ(term.particles.size(), members.size());
    EXPECT_DOUBLE_EQ(term.weight, 1.0 / (88.844 * 88.844 * 100));
    for (std::size_t k = 0; k < term.frame_steps.size(); ++k) {
      const std::size_t f = k + 1;  // frame 0 precedes the first step
      EXPECT_EQ(term.frame_steps[k], f * 20);
      const std::array<double, 3> c = Centroid(whole, f, members);
      for (int a = 0; a < 3; ++a) EXPECT_EQ(term.reference[k][0][a], c[a]) << g << " " << f;
    }
  }
  const std::unique_ptr<FrameSource> again = OpenFrameSource(file);
  const auto particle = TrackLoss(*again, Track{5, "", Axis::kY}, steps, 1.0);
  ASSERT_EQ(particle.size(), 1u);
  EXPECT_EQ(particle[0].axis_weight, (engine::Vec3d{0, 1, 0}));
  EXPECT_EQ(particle[0].reference[9][0][1], double(whole.coordinate(10, 5, 1)));
  EXPECT_THROW(TrackLoss(*again, Track{whole.particle_count(), "", Axis::kY}, steps, 1.0),
               InputError);
}

}  // namespace
}  // namespace owval::sgd
