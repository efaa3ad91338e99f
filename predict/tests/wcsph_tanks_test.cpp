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
#include "owval/testing/scratch_directory.hpp"
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

const ReconcileRow& TankRow(const Reconciliation& r, const std::string& quantity) {
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
  const ReconcileRow& mean = TankRow(run.reconciliation, "mid_depth_pressure");
  ASSERT_TRUE(mean.measured.has_value());
  EXPECT_TRUE(run.reconciliation.pass) << ReconcileMarkdown(run.reconciliation);
  EXPECT_LE(std::abs(*mean.gap), 0.05);
  ASSERT_TRUE(TankRow(run.reconciliation, "mid_depth_pressure_rms_error").measured.has_value());
  // The optimistic steps stay within the rollback threshold: no accepted sub-step above 3%.
  EXPECT_GT(run.substeps, 0);
  EXPECT_LE(run.max_density_variation, 0.03);
}

TEST(WcsphHydrostaticTank, WithoutDensityDiffusionTheDensityAndThePressureVaryMore) {
  const TankRun without = RunSmallTank(false);
  EXPECT_GT(without.max_density_variation, WithDiffusion().max_density_variation);
  const auto error = [](const TankRun& run) {
    return *TankRow(run.reconciliation, "mid_depth_pressure_rms_error").measured;
  };
  EXPECT_GT(error(without), error(WithDiffusion()));
}

// A small dam break (a = 8 sites, 3 deep) to T = 2.6: the front measured by reconcile leaves the
// column face and advances, and stays behind the shallow-water (Ritter) dry-bed front, which
// moves at 2 √(g H) = 2 in Z per unit T for H = 2a: Z(T) < 1 + 2T. A wrong time unit, a wrong
// wall face or a front picked from splashed particles breaks one of the bounds.
TEST(WcsphDamBreak, FrontAdvancesAndStaysBehindTheShallowWaterFront) {
  const engine::SiberneticConfig c = scenarios::Generate(
      "dam_break",
      {{"column_sites", 8}, {"tank_sites", 40}, {"sites_z", 3}, {"headroom_layers", 2}});
  engine::RunOptions o;
  o.backend = "wcsph";
  engine::SetConstant(&o.constants, "time_step_s", 1e-4);
  o.duration_s = 0.006;
  o.log_step = 2;
  engine::RunSummary summary;
  const Trajectory t = engine::Run(c, o, &summary);
  PredictOptions p;
  p.predictor = "dam_break";
  const Reconciliation r = Reconcile(Predict(c, engine::PhysicsConstants{}, p), t);
  double previous = 1;
  int measured = 0;
  for (const ReconcileRow& row : r.rows) {
    const std::string prefix = "surge_front_Z_at_T_";
    if (row.quantity.rfind(prefix, 0) != 0 || !row.measured) continue;
    const double big_t = std::stod(row.quantity.substr(prefix.size()));
    EXPECT_GT(*row.measured, previous) << row.quantity;
    EXPECT_LT(*row.measured, 1 + 2 * big_t) << row.quantity;
    previous = *row.measured;
    ++measured;
  }
  EXPECT_GE(measured, 4);  // the gated points up to T = 2.547
  // Koshizuka & Oka's series rides along, informative.
  EXPECT_EQ(TankRow(r, "koshizuka_oka_front_Z_at_T_1.153").tolerance_kind,
            ToleranceKind::kInformative);
}

// Issue 16: reconciled frame by frame from the run's HDF5 file (positions and pressure
// streamed), every row is the whole trajectory's, value for value.
TEST(WcsphHydrostaticTank, ReconciledFromTheStreamedFileEqualsTheWholeTrajectory) {
  const TankRun& run = WithDiffusion();
  const std::filesystem::path h5 = owval::testing::TestScratch() / "tank.h5";
  WriteHdf5(run.trajectory, h5);
  const auto frames = OpenFrameSource(h5);
  EXPECT_EQ(Reconcile(run.prediction, *frames).ToJson().dump(), run.reconciliation.ToJson().dump());
  std::filesystem::remove(h5);
}

}  // namespace
}  // namespace owval::predict
