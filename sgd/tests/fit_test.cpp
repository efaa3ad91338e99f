#include "owval/sgd/fit.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <future>

#include <unistd.h>

#include "owval/base/errors.hpp"
#include "owval/sgd/targets.hpp"
#include "owval/testing/scratch_directory.hpp"
#include "owval/trajectory/formats.hpp"

namespace owval::sgd {
namespace {

// A closed-form stand-in for one_sprig: period T(k) = 2π/√(k/4) against a target period, and a
// second residual with a known optimum. The exact optimum is k* = 3e8.
std::vector<double> SpringResiduals(const std::vector<double>& x) {
  const double kPi = 3.14159265358979;
  const double target_period = 2 * kPi / std::sqrt(3e8 / 4);
  const double period = 2 * kPi / std::sqrt(x[0] / 4);
  return {(period - target_period) / 0.725e-3, 0.5 * (x[0] / 3e8 - 1)};
}

class ClosedForm : public ::testing::TestWithParam<Solver> {};

TEST_P(ClosedForm, ReachesTheKnownOptimumFromFarAway) {
  FitOptions options;
  options.solver = GetParam();
  options.loss_threshold = 1e-10;
  options.max_iterations = 200;
  FitSummary summary;
  Fit(options, {{"elasticity_coefficient", 1.62e8, true, 1e6, 1e10}}, SpringResiduals, &summary);
  EXPECT_TRUE(summary.converged) << summary.BriefReport();
  EXPECT_NEAR(summary.final_values[0], 3e8, 3e8 * 1e-4);
  EXPECT_LT(summary.final_loss, 1e-10);
  ASSERT_FALSE(summary.iterations.empty());
  EXPECT_NEAR(summary.iterations.front().values[0], 1.62e8, 1.62e8 * 1e-12);  // the start
  EXPECT_EQ(summary.iterations.back().evaluations, summary.evaluations);
}

INSTANTIATE_TEST_SUITE_P(Solvers, ClosedForm,
                         ::testing::Values(Solver::kLevenbergMarquardt, Solver::kDogleg,
                                           Solver::kGradientDescent));

TEST(Fit, TwoParametersWithBounds) {
  // Minimum of (x-2)² + (y+1)² outside y's bounds [0, 5]: the fit stops at y = 0.
  FitOptions options;
  options.loss_threshold = 0;  // run to Ceres' own convergence
  FitSummary summary;
  Fit(
      options, {{"x", 0.0, false}, {"y", 3.0, false, 0.0, 5.0}},
      [](const std::vector<double>& v) {
        return std::vector<double>{v[0] - 2, v[1] + 1};
      },
      &summary);
  // Ceres stops on its relative cost tolerance (1e-6), so x is within ~1e-4 of its optimum.
  EXPECT_NEAR(summary.final_values[0], 2, 1e-3);
  EXPECT_NEAR(summary.final_values[1], 0, 1e-9);  // held exactly at its bound
  EXPECT_NEAR(summary.final_loss, 1, 1e-6);
}

TEST(Fit, HistoryJsonFollowsTheDocumentedSchema) {
  FitOptions options;
  FitSummary summary;
  const std::vector<Parameter> parameters = {{"k", 1.62e8, true}};
  Fit(options, parameters, SpringResiduals, &summary);
  const nlohmann::json h = ToJson(options, parameters, summary);
  // Required keys and types, as docs/fit_history.md lists them.
  EXPECT_EQ(h.at("schema"), "owval.fit.history/2");
  EXPECT_TRUE(h.at("solver").is_string());
  EXPECT_TRUE(h.at("loss_threshold").is_number());
  EXPECT_TRUE(h.at("parameters").is_array());
  EXPECT_TRUE(h.at("converged").is_boolean());
  EXPECT_TRUE(h.at("stop_reason").is_string());
  EXPECT_TRUE(h.at("evaluations").is_number_integer());
  EXPECT_TRUE(h.at("final").at("parameters").at("k").is_number());
  ASSERT_FALSE(h.at("iterations").empty());
  for (const auto& it : h.at("iterations")) {
    for (const char* key : {"loss", "wall_s"}) EXPECT_TRUE(it.at(key).is_number()) << key;
    for (const char* key : {"residuals", "gradient", "step"})
      EXPECT_TRUE(it.at(key).is_array()) << key;
    EXPECT_TRUE(it.at("evaluations").is_number_integer());
    EXPECT_TRUE(it.at("parameters").at("k").is_number());
  }
}

TEST(Fit, CancellationKeepsTheHistory) {
  FitOptions options;
  options.solver = Solver::kGradientDescent;
  options.learning_rate = 1e-3;  // slow on purpose
  int seen = 0;
  options.on_iteration = [&](const nlohmann::json&) { ++seen; };
  options.cancelled = [&] { return seen >= 2; };
  FitSummary summary;
  Fit(options, {{"k", 1.62e8, true}}, SpringResiduals, &summary);
  EXPECT_EQ(summary.stop_reason, "cancelled");
  EXPECT_EQ(summary.iterations.size(), 2u);
}

// A gradient-descent step that left what the simulation takes (--learning-rate 1e300 made
// elasticity_coefficient infinite) ended the fit with exit 2 after its first history was written.
// As Ceres does, the step is shortened instead; an unphysical start is still bad input.
TEST(Fit, AGradientStepTheSimulationRefusesIsShortened) {
  const auto physical_only = [](const std::vector<double>& x) {
    if (!(x[0] > 1e6 && x[0] < 1e10)) throw InputError("engine constant k is not physical");
    return SpringResiduals(x);
  };
  FitOptions options;
  options.solver = Solver::kGradientDescent;
  options.learning_rate = 1e6;  // every first step leaves (1e6, 1e10)
  options.max_iterations = 60;
  options.loss_threshold = 1e-6;
  FitSummary summary;
  Fit(options, {{"k", 1.62e8, true}}, physical_only, &summary);
  EXPECT_TRUE(summary.converged) << summary.BriefReport();
  EXPECT_NEAR(summary.final_values[0], 3e8, 3e8 * 1e-2);
  FitSummary refused;
  EXPECT_THROW(Fit(options, {{"k", 1e11, true}}, physical_only, &refused), InputError);
}

TEST(Targets, ParseTargetAndParameterSpecifications) {
  const Target t = ParseTarget("half_amplitude=1.694:scale=1.694:weight=0.25");
  EXPECT_EQ(t.metric, "half_amplitude");
  EXPECT_DOUBLE_EQ(t.value, 1.694);
  EXPECT_DOUBLE_EQ(t.weight, 0.25);
  const Parameter p = ParseParameter("elasticity_coefficient=1.62e8:log:1e6:1e10");
  EXPECT_TRUE(p.log_space);
  EXPECT_DOUBLE_EQ(p.upper, 1e10);
  EXPECT_THROW(ParseTarget("period=abc"), InputError);
  EXPECT_THROW(ParseParameter("k=-1:log"), InputError);
  EXPECT_THROW(ParseTarget("period=1:color=red"), InputError);
}

// `--param elasticity_coefficient=1.62e8:log:1e9:1e8` (lower > upper) reached Ceres, which
// printed several lines and the fit wrote a history with loss 0 and exit 1.
TEST(Targets, ParameterBoundsMustBeOrderedAndEncloseTheStart) {
  EXPECT_THROW(ParseParameter("elasticity_coefficient=1.62e8:log:1e9:1e8"), InputError);
  EXPECT_THROW(ParseParameter("k=5:1:1"), InputError);      // empty interval
  EXPECT_THROW(ParseParameter("k=5:lin:6:7"), InputError);  // start below
  EXPECT_THROW(ParseParameter("k=8:lin:6:7"), InputError);  // start above
  EXPECT_NO_THROW(ParseParameter("k=6:lin:6:7"));           // on a bound
  EXPECT_NO_THROW(ParseParameter("k=1.62e8:log:1e8:1e9"));
}

// An empty --param or --target printed libstdc++'s "vector::_M_range_check: __n (which is 0) >=
// this->size() (which is 0)"; weight=-5 made every residual NaN once the first simulation had
// run; a repeated option kept its last value silently.
TEST(Targets, EmptyNegativeWeightAndRepeatedOptionsAreRefusedNamingTheText) {
  auto error = [](auto parse, const std::string& text) -> std::string {
    try {
      parse(text);
    } catch (const InputError& e) {
      return e.what();
    }
    return "accepted";
  };
  EXPECT_EQ(error(ParseTarget, ""), "--target : expected NAME=VALUE, found ''");
  EXPECT_EQ(error(ParseParameter, ""), "--param : expected NAME=VALUE, found ''");
  EXPECT_EQ(error(ParseTarget, "period=1:weight=-5"),
            "--target period=1:weight=-5: weight must be 0 or more");
  EXPECT_EQ(error(ParseTarget, "period=1:weight=0"), "accepted");
  EXPECT_EQ(error(ParseTarget, "period=1:scale=1:scale=2"),
            "--target period=1:scale=1:scale=2: scale is given twice");
  EXPECT_EQ(error(ParseParameter, "k=5:lin:nan:7"),
            "--param k=5:lin:nan:7: lower bound: expected a number, found 'nan'");
}

// One particle at y = 1, 2, 3 over three frames, shifted by `dy`.
Trajectory Line(double dy) {
  Trajectory t;
  t.box = {0, 10, 0, 10, 0, 10};
  t.time_step_s = 1e-3;
  t.type = {1.1f};
  t.time_s = {0, 1e-3, 2e-3};
  for (int f = 0; f < 3; ++f) t.positions.insert(t.positions.end(), {5, float(1 + f + dy), 5});
  return t;
}

// The reference of an rms target is read once, when the objective is made: finite-difference
// points run on threads of their own, and reading HDF5 there (a fork from a busy process) left a
// sanitizer build's containment child hung until its timeout, failing the fit.
TEST(Targets, RmsReferenceIsReadOnceWhenTheObjectiveIsMade) {
  const std::filesystem::path dir = owval::testing::TestScratch("rms");
  const std::filesystem::path reference = dir / "reference.h5";
  WriteTrajectory(Line(0), reference);
  const Objective objective =
      MakeObjective([](const std::vector<double>& x,
                       const Track& track) { return TrackedSeriesOf(Line(x[0]), track); },
                    Track{}, {ParseTarget("rms=0:scale=2:ref=" + reference.string())});
  std::filesystem::remove_all(dir);  // evaluations must not need the file any more
  std::vector<std::future<std::vector<double>>> points;
  for (double dy : {0.5, 1.0, 3.0})
    points.push_back(std::async(std::launch::async, [&objective, dy] { return objective({dy}); }));
  EXPECT_DOUBLE_EQ(points[0].get().at(0), 0.25);
  EXPECT_DOUBLE_EQ(points[1].get().at(0), 0.5);
  EXPECT_DOUBLE_EQ(points[2].get().at(0), 1.5);
  EXPECT_THROW(MakeObjective([](const std::vector<double>&,
                                const Track& track) { return TrackedSeriesOf(Line(0), track); },
                             Track{}, {ParseTarget("rms=0:ref=" + reference.string())}),
               InputError);  // unreadable now: refused before any evaluation
}

}  // namespace
}  // namespace owval::sgd

#include "owval/sgd/finite_difference.hpp"

namespace owval::sgd {
namespace {

TEST(FiniteDifference, PassesForTheRightDerivativeAndFailsForAWrongOne) {
  // d/du of exp(-u/2) at u = log(3e8): the period's response to log stiffness, T ∝ k^(-1/2).
  const auto f = [](double u) { return std::exp(-u / 2); };
  FiniteDifferenceTest right{"period vs log k", std::log(3e8), 1e-2,
                             -0.5 * std::exp(-std::log(3e8) / 2), 0.02};
  RunFiniteDifferenceTest(f, &right);
  EXPECT_TRUE(right.pass) << right.ToJson().dump();
  FiniteDifferenceTest wrong = right;
  wrong.analytic *= 2;  // the 0.25-factor class of mistake
  RunFiniteDifferenceTest(f, &wrong);
  EXPECT_FALSE(wrong.pass);
}

}  // namespace
}  // namespace owval::sgd
