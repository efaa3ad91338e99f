// owval fit --gradient analytic: Ceres L-BFGS on the XPBD reverse pass's gradient.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "owval/engine/config.hpp"
#include "owval/sgd/gradient_fit.hpp"

namespace owval::sgd {
namespace {

const std::filesystem::path kOneSprig =
    std::filesystem::path(OWVAL_SHARED_DIR) / "reference/one_sprig/configuration";

// Particle 0's y at every step of the model's own run at the default stiffness.
std::vector<engine::LossTerm> SprigLoss(const engine::DifferentiableXpbd& model,
                                        std::size_t steps) {
  const auto frames = model.Trajectory(model.DefaultParameters(), steps);
  engine::LossTerm term;
  term.particles = {0};
  term.axis_weight = {0, 1, 0};
  for (std::size_t t = 1; t <= steps; ++t) {
    term.frame_steps.push_back(t);
    term.reference.push_back({frames[t - 1][0]});
  }
  term.weight = 1.0 / double(steps);
  return {term};
}

// A fit of one_sprig's stiffness from 0.54 k to SprigLoss over `steps` steps.
GradientFitSummary FitSprigFromHalfStiffness(GradientFitOptions o, std::size_t steps) {
  const engine::DifferentiableXpbd model(engine::ReadSiberneticConfig(kOneSprig),
                                         engine::PhysicsConstants{});
  o.reverse.steps = steps;
  GradientFitSummary s;
  FitWithGradient(o, model, {{"elasticity_coefficient", 0.54 * 3e8, true}}, SprigLoss(model, steps),
                  &s);
  return s;
}

// 30 steps, 0.83 of a period: with substeps the spring hardly damps, and over 100 steps (2.8
// periods) the loss in k has a local minimum per period of phase lag (L-BFGS from 0.54 k then
// stops at k = 8.4e7, L = 2.37).
TEST(GradientFit, OneSprigFromHalfStiffnessConvergesWithinSevenIterations) {
  const engine::DifferentiableXpbd model(engine::ReadSiberneticConfig(kOneSprig),
                                         engine::PhysicsConstants{});
  GradientFitOptions o;
  o.reverse.steps = 30;
  GradientFitSummary s;
  FitWithGradient(o, model, {{"elasticity_coefficient", 0.54 * 3e8, true}}, SprigLoss(model, 30),
                  &s);
  EXPECT_TRUE(s.fit.converged) << s.fit.BriefReport();
  EXPECT_LT(s.fit.final_loss, 1e-4);
  ASSERT_FALSE(s.fit.iterations.empty());
  EXPECT_LE(s.fit.iterations.back().iteration, 7);
  EXPECT_NEAR(s.fit.final_values[0], 3e8, 0.01 * 3e8);
  EXPECT_GT(s.fit.iterations.front().loss, 0.1);
  const nlohmann::json j = ToJson(o, {{"elasticity_coefficient", 0.54 * 3e8, true}}, s);
  EXPECT_EQ(j["gradient"], "analytic");
  EXPECT_TRUE(j["iterations"][0].contains("gradient_norm"));
  EXPECT_TRUE(j["iterations"][0].contains("simulation_equivalents"));
}

TEST(GradientFit, UnknownParameterIsBadInput) {
  const engine::DifferentiableXpbd model(engine::ReadSiberneticConfig(kOneSprig),
                                         engine::PhysicsConstants{});
  GradientFitOptions o;
  o.reverse.steps = 10;
  GradientFitSummary s;
  EXPECT_THROW(
      FitWithGradient(o, model, {{"pcisph_iterations", 3, false}}, SprigLoss(model, 10), &s),
      std::exception);
}

TEST(GradientFit, OscillatorSurrogateIsZeroOnTheOscillation) {
  const auto loss = OscillatorLoss(0, 1, 1e-3, 10, 12, 2e-5, 50, 1);
  ASSERT_EQ(loss.size(), 1u);
  ASSERT_EQ(loss[0].reference.size(), 50u);
  EXPECT_DOUBLE_EQ(loss[0].reference[49][0][1],
                   10 + 2 * std::cos(2 * 3.141592653589793 * 0.05 * 20));
  EXPECT_DOUBLE_EQ(loss[0].weight, 1.0 / 50);
}

}  // namespace
}  // namespace owval::sgd

namespace owval::sgd {
namespace {

TEST(GradientFit, AdamLowersTheOneSprigLossInLogSpace) {
  GradientFitOptions o;
  o.method = GradientFitOptions::Method::kAdam;
  o.learning_rate = 0.1;
  o.max_iterations = 6;
  const GradientFitSummary s = FitSprigFromHalfStiffness(o, 50);
  ASSERT_EQ(s.fit.iterations.size(), 7u);
  EXPECT_LT(s.fit.iterations.back().loss, 0.5 * s.fit.iterations.front().loss);
  EXPECT_GT(s.fit.final_values[0], 0.54 * 3e8);  // moved up, toward the true k
  EXPECT_EQ(ToJson(o, {{"elasticity_coefficient", 0.54 * 3e8, true}}, s)["solver"], "adam");
}

// Adam's steps do not shrink: at a large rate it overshoots the true k and wanders, so the
// result is the best iterate and the fit ends as stalled once the best loss stops falling.
TEST(GradientFit, AdamReturnsItsBestIterateAndStopsWhenStalled) {
  GradientFitOptions o;
  o.method = GradientFitOptions::Method::kAdam;
  o.learning_rate = 0.5;
  o.max_iterations = 60;
  o.loss_threshold = 0;  // never met: only the stall rule can end it early
  o.patience = 4;
  const GradientFitSummary s = FitSprigFromHalfStiffness(o, 30);
  ASSERT_LT(s.fit.iterations.size(), 61u) << s.fit.BriefReport();
  EXPECT_NE(s.fit.stop_reason.find("stalled"), std::string::npos) << s.fit.stop_reason;
  const auto best =
      std::min_element(s.fit.iterations.begin(), s.fit.iterations.end(),
                       [](const Iteration& a, const Iteration& b) { return a.loss < b.loss; });
  EXPECT_EQ(s.fit.final_loss, best->loss);
  EXPECT_EQ(s.fit.final_values, best->values);
  EXPECT_LT(s.fit.final_loss, s.fit.iterations.back().loss);  // it did wander off the best
  // The last `patience` iterations did not beat the best by 0.1%.
  for (std::size_t i = s.fit.iterations.size() - 4; i < s.fit.iterations.size(); ++i)
    EXPECT_GE(s.fit.iterations[i].loss, best->loss * (1 - 1e-3) - 1e-300);
}

// Ctrl-C in `owval fit --gradient analytic` (StopSignals -> cancelled): both solvers stop after
// the iteration in progress, with the history so far.
TEST(GradientFit, CancellationStopsEitherSolverAfterTheIterationInProgress) {
  for (const auto method :
       {GradientFitOptions::Method::kAdam, GradientFitOptions::Method::kLbfgs}) {
    GradientFitOptions o;
    o.method = method;
    o.max_iterations = 20;
    o.loss_threshold = 0;
    int polls = 0;
    o.cancelled = [&polls] { return ++polls >= 2; };
    const GradientFitSummary s = FitSprigFromHalfStiffness(o, 30);
    EXPECT_EQ(s.fit.stop_reason, "cancelled");
    EXPECT_EQ(polls, 2);
    EXPECT_EQ(s.fit.iterations.size(), 2u);
    EXPECT_FALSE(s.fit.converged);
  }
}

}  // namespace
}  // namespace owval::sgd
