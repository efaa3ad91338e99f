#pragma once
// Parameter fitting (phase 5): every tuned value comes from an optimiser whose history is saved.
// The objective is a vector of scaled residuals r_i(θ); the loss is L = Σ r_i². Ceres
// (Levenberg–Marquardt or dogleg) solves it with central finite-difference derivatives (each
// residual evaluation may be a whole simulation), or a plain gradient descent does, as the
// contributors' SGD scripts did. Usage mirrors Ceres: Fit(options, parameters, objective,
// &summary).
#include <chrono>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace owval::sgd {

struct Parameter {
  std::string name;
  double start = 1;
  bool log_space = false;  // stiffness-like, positive: optimised as log(value)
  double lower = -1e300, upper = 1e300;
};

// θ (in the parameters' own units) → scaled residuals. Must be safe to call from several threads
// at once when FitOptions::parallel_evaluations is true.
using Objective = std::function<std::vector<double>(const std::vector<double>& values)>;

enum class Solver { kLevenbergMarquardt, kDogleg, kGradientDescent };
Solver ParseSolver(const std::string& name);  // lm | dogleg | gd
const char* SolverName(Solver solver);

struct FitOptions {
  Solver solver = Solver::kLevenbergMarquardt;
  double loss_threshold = 1e-4;  // stop as soon as L < this
  int max_iterations = 20;
  double relative_fd_step = 1e-3;  // central differences: h = step·max(|x|, 1) in internal coords
  bool parallel_evaluations = true;  // evaluate the 2n finite-difference points concurrently
  double learning_rate = 0.5;        // gradient descent, internal coordinates
  // Called after each iteration with the history so far (e.g. to write history.json).
  std::function<void(const nlohmann::json& history)> on_iteration;
  // Polled between evaluations; returning true stops the fit (Ctrl-C).
  std::function<bool()> cancelled;
};

struct Iteration {
  int iteration = 0;
  std::vector<double> values;  // parameters, own units
  double loss = 0;
  std::vector<double> residuals;
  std::vector<double> gradient;  // dL/dθ in internal coordinates (log for log-space)
  std::vector<double> step;      // change of internal coordinates since the previous iteration
  int evaluations = 0;           // objective evaluations (simulations) so far
  double wall_s = 0;
};

struct FitSummary {
  std::vector<Iteration> iterations;
  std::vector<double> final_values;
  double final_loss = 0;
  int evaluations = 0;
  bool converged = false;  // final loss below the threshold
  std::string stop_reason;
  double wall_s = 0;
  std::string BriefReport() const;
};

// Runs the fit. The history JSON (schema in docs/fit_history.md) is available from ToJson().
void Fit(const FitOptions& options, const std::vector<Parameter>& parameters,
         const Objective& objective, FitSummary* summary);

nlohmann::json ToJson(const FitOptions& options, const std::vector<Parameter>& parameters,
                      const FitSummary& summary,
                      const nlohmann::json& targets = nlohmann::json::array());

}  // namespace owval::sgd
