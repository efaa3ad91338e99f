// The WCSPH scenarios end to end, as the harness runs them: generate, run the wcsph backend,
// predict, reconcile. A small hydrostatic tank (6 x 12 x 3 liquid sites) settles in seconds of
// wall time; the full-size runs and the dam break are in docs/benchmarks.md (WCSPH).
#include <gtest/gtest.h>

#include <unistd.h>
#include <algorithm>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "owval/engine/constants.hpp"
#include "owval/engine/run.hpp"
#include "owval/predict/predict.hpp"
#include "owval/scenarios/generators.hpp"
#include "owval/trajectory/formats.hpp"
#include "owval/trajectory/frame_source.hpp"

namespace owval::predict {
namespace {

struct TankRun {
  Trajectory trajectory;
  Prediction prediction;
  Reconciliation reconciliation;
  double max_density_variation = 0;  // over every accepted sub-step
  long rollbacks = 0, substeps = 0;
};

// 10 ms (about 4 √(H/g)) of a 12-row column at Sibernetic's scale, nominal step 1e-4 s.
TankRun RunSmallTank(bool density_diffusion) {
  const engine::SiberneticConfig c = scenarios::Generate(
      "hydrostatic_tank", {{"sites_x", 6}, {"sites_z", 3}, {"layers", 12}, {"headroom_layers", 2}});
  engine::RunOptions o;
  o.backend = "wcsph";
  engine::SetConstant(&o.constants, "time_step_s", 1e-4);
  engine::SetConstant(&o.constants, "wcsph_density_diffusion", density_diffusion ? 1 : 0);
  o.duration_s = 0.01;
  o.log_step = 5;
  engine::RunSummary summary;
  const Trajectory t = engine::Run(c, o, &summary);
  PredictOptions p;
  p.predictor = "hydrostatic_tank";
  TankRun run;
  run.trajectory = t;
  run.prediction = Predict(c, engine::PhysicsConstants{}, p);
  run.reconciliation = Reconcile(run.prediction, t);
  for (const std::string& frame : summary.frame_log) {
    const nlohmann::json log = nlohmann::json::parse(frame);
    run.max_density_variation =
        std::max(run.max_density_variation, log["max_density_variation_interval"].get<double>());
    run.rollbacks = log["rollbacks_total"].get<long>();
    run.substeps = log["substeps_total"].get<long>();
  }
  return run;
}

const ReconcileRow& Row(const Reconciliation& r, const std::string& quantity) {
  for (const ReconcileRow& row : r.rows)
    if (row.quantity == quantity) return row;
  throw std::runtime_error("no row " + quantity);
}

// The run with δ-SPH, shared by the tests (one run).
const TankRun& WithDiffusion() {
  static const TankRun run = RunSmallTank(true);
  return run;
}

TEST(WcsphHydrostaticTank, SettlesToTheHydrostaticPressureAtMidDepthWithinFivePercent) {
  const TankRun& run = WithDiffusion();
  const ReconcileRow& mean = Row(run.reconciliation, "mid_depth_pressure");
  ASSERT_TRUE(mean.measured.has_value());
  EXPECT_TRUE(run.reconciliation.pass) << ReconcileMarkdown(run.reconciliation);
  EXPECT_LE(std::abs(*mean.gap), 0.05);
  ASSERT_TRUE(Row(run.reconciliation, "mid_depth_pressure_rms_error").measured.has_value());
  // The optimistic steps stay within the rollback threshold: no accepted sub-step above 3%.
  EXPECT_GT(run.substeps, 0);
  EXPECT_LE(run.max_density_variation, 0.03);
}

TEST(WcsphHydrostaticTank, WithoutDensityDiffusionTheDensityAndThePressureVaryMore) {
  const TankRun without = RunSmallTank(false);
  EXPECT_GT(without.max_density_variation, WithDiffusion().max_density_variation);
  const auto error = [](const TankRun& run) {
    return *Row(run.reconciliation, "mid_depth_pressure_rms_error").measured;
  };
  EXPECT_GT(error(without), error(WithDiffusion()));
}

// Issue 16: reconciled frame by frame from the run's HDF5 file (positions and pressure
// streamed), every row is the whole trajectory's, value for value.
TEST(WcsphHydrostaticTank, ReconciledFromTheStreamedFileEqualsTheWholeTrajectory) {
  const TankRun& run = WithDiffusion();
  const std::filesystem::path h5 =
      std::filesystem::temp_directory_path() / ("owval_tank_" + std::to_string(::getpid()) + ".h5");
  WriteHdf5(run.trajectory, h5);
  const auto frames = OpenFrameSource(h5);
  EXPECT_EQ(Reconcile(run.prediction, *frames).ToJson().dump(), run.reconciliation.ToJson().dump());
  std::filesystem::remove(h5);
}

}  // namespace
}  // namespace owval::predict
