#include "owval/sgd/fit.hpp"

#include <ceres/ceres.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <future>
#include <mutex>
#include <sstream>

#include "owval/base/errors.hpp"
#include "owval/sgd/fit_record.hpp"

namespace owval::sgd {
namespace {

using Clock = std::chrono::steady_clock;

// The objective seen in internal coordinates u (log(x) for log-space parameters), with
// central finite-difference Jacobians and a record of every point evaluated.
class Problem {
 public:
  Problem(const FitOptions& options, const std::vector<Parameter>& parameters,
          const Objective& objective)
      : options_(options), parameters_(parameters), objective_(objective), start_(Clock::now()) {}

  std::vector<double> ToInternal(const std::vector<double>& x) const {
    std::vector<double> u(x.size());
    for (std::size_t i = 0; i < x.size(); ++i)
      u[i] = parameters_[i].log_space ? std::log(x[i]) : x[i];
    return u;
  }
  std::vector<double> ToValues(const std::vector<double>& u) const {
    std::vector<double> x(u.size());
    for (std::size_t i = 0; i < u.size(); ++i)
      x[i] = parameters_[i].log_space ? std::exp(u[i]) : u[i];
    return x;
  }
  double Lower(std::size_t i) const {
    const Parameter& p = parameters_[i];
    return p.log_space ? (p.lower > 0 ? std::log(p.lower) : -1e300) : p.lower;
  }
  double Upper(std::size_t i) const {
    const Parameter& p = parameters_[i];
    return p.log_space ? std::log(p.upper) : p.upper;
  }

  std::vector<double> Residuals(const std::vector<double>& u) {
    if (options_.cancelled && options_.cancelled()) throw Cancelled();
    ++evaluations_;
    std::vector<double> r = objective_(ToValues(u));
    for (double v : r)
      if (!std::isfinite(v)) throw InputError("the objective returned a non-finite residual");
    std::lock_guard<std::mutex> lock(mutex_);
    recent_.push_back({u, r, {}});
    if (recent_.size() > 8) recent_.erase(recent_.begin());
    return r;
  }

  bool Cached(const std::vector<double>& u, std::vector<double>* r) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const Point& p : recent_)
      if (p.u == u) {
        *r = p.residuals;
        return true;
      }
    return false;
  }

  // Residuals at u and, by central differences, their Jacobian (row-major m x n).
  std::vector<double> ResidualsAndJacobian(const std::vector<double>& u,
                                           std::vector<double>* jacobian) {
    const std::size_t n = u.size();
    std::vector<std::vector<double>> points(2 * n + 1, u);
    std::vector<double> h(n);
    for (std::size_t j = 0; j < n; ++j) {
      h[j] = options_.relative_fd_step * std::max(std::abs(u[j]), 1.0);
      points[1 + 2 * j][j] += h[j];
      points[2 + 2 * j][j] -= h[j];
    }
    std::vector<std::vector<double>> results(points.size());
    // Ceres evaluates a trial point's residuals before asking for the Jacobian there: reuse them.
    const std::size_t first = Cached(u, &results[0]) ? 1 : 0;
    if (options_.parallel_evaluations) {
      std::vector<std::future<std::vector<double>>> futures;
      for (std::size_t k = first; k < points.size(); ++k)
        futures.push_back(
            std::async(std::launch::async, [this, p = points[k]] { return Residuals(p); }));
      for (std::size_t k = first; k < points.size(); ++k) results[k] = futures[k - first].get();
    } else {
      for (std::size_t k = first; k < points.size(); ++k) results[k] = Residuals(points[k]);
    }
    const std::size_t m = results[0].size();
    jacobian->assign(m * n, 0.0);
    for (std::size_t j = 0; j < n; ++j)
      for (std::size_t i = 0; i < m; ++i)
        (*jacobian)[i * n + j] = (results[1 + 2 * j][i] - results[2 + 2 * j][i]) / (2 * h[j]);
    Remember(u, results[0], *jacobian);
    return results[0];
  }

  // The iteration record at u, from what was evaluated there.
  Iteration Record(int iteration, const std::vector<double>& u,
                   const std::vector<double>& previous_u) {
    std::lock_guard<std::mutex> lock(mutex_);
    Iteration it;
    it.iteration = iteration;
    it.values = ToValues(u);
    for (const Point& p : points_) {
      if (p.u != u) continue;
      it.residuals = p.residuals;
      const std::size_t n = u.size(), m = p.residuals.size();
      it.gradient.assign(n, 0.0);
      for (std::size_t j = 0; j < n; ++j)
        for (std::size_t i = 0; i < m; ++i)
          it.gradient[j] += 2 * p.jacobian[i * n + j] * p.residuals[i];
    }
    for (double r : it.residuals) it.loss += r * r;
    it.step.resize(u.size(), 0.0);
    if (!previous_u.empty())
      for (std::size_t j = 0; j < u.size(); ++j) it.step[j] = u[j] - previous_u[j];
    it.evaluations = evaluations_;
    it.wall_s = std::chrono::duration<double>(Clock::now() - start_).count();
    return it;
  }

  int evaluations() const { return evaluations_; }
  double elapsed_s() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }

 private:
  struct Point {
    std::vector<double> u, residuals, jacobian;
  };
  void Remember(const std::vector<double>& u, const std::vector<double>& r,
                const std::vector<double>& j) {
    std::lock_guard<std::mutex> lock(mutex_);
    points_.push_back({u, r, j});
  }

  const FitOptions& options_;
  const std::vector<Parameter>& parameters_;
  const Objective& objective_;
  std::atomic<int> evaluations_{0};
  std::mutex mutex_;
  std::vector<Point> points_;
  std::vector<Point> recent_;  // the last residual-only evaluations
  Clock::time_point start_;
};

class FiniteDifferenceCost : public ceres::CostFunction {
 public:
  FiniteDifferenceCost(Problem* problem, int residuals, int parameters) : problem_(problem) {
    set_num_residuals(residuals);
    mutable_parameter_block_sizes()->push_back(parameters);
  }
  bool Evaluate(double const* const* blocks, double* residuals, double** jacobians) const override {
    const std::size_t n = parameter_block_sizes()[0];
    const std::vector<double> u(blocks[0], blocks[0] + n);
    try {
      std::vector<double> r;
      if (jacobians && jacobians[0]) {
        std::vector<double> jac;
        r = problem_->ResidualsAndJacobian(u, &jac);
        std::copy(jac.begin(), jac.end(), jacobians[0]);
      } else {
        r = problem_->Residuals(u);
      }
      std::copy(r.begin(), r.end(), residuals);
      return true;
    } catch (const InputError&) {
      return false;  // e.g. the simulation went unstable: Ceres shrinks the step
    } catch (const Cancelled&) {
      return false;  // never unwind through Ceres: the callback aborts the solve
    }
  }

 private:
  Problem* problem_;
};

class HistoryCallback : public ceres::IterationCallback {
 public:
  HistoryCallback(Problem* problem, const double* block, std::size_t n, const FitOptions& options,
                  const std::vector<Parameter>& parameters, FitSummary* summary)
      : problem_(problem),
        block_(block),
        n_(n),
        options_(options),
        parameters_(parameters),
        summary_(summary) {}

  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override {
    if (options_.cancelled && options_.cancelled()) return ceres::SOLVER_ABORT;
    if (s.iteration > 0 && !s.step_is_successful) return ceres::SOLVER_CONTINUE;
    const std::vector<double> u(block_, block_ + n_);
    summary_->iterations.push_back(problem_->Record(s.iteration, u, previous_u_));
    previous_u_ = u;
    if (options_.on_iteration) options_.on_iteration(ToJson(options_, parameters_, *summary_));
    if (summary_->iterations.back().loss < options_.loss_threshold)
      return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
    return ceres::SOLVER_CONTINUE;
  }

 private:
  Problem* problem_;
  const double* block_;
  std::size_t n_;
  const FitOptions& options_;
  const std::vector<Parameter>& parameters_;
  FitSummary* summary_;
  std::vector<double> previous_u_;
};

std::string SolveWithCeres(const FitOptions& o, const std::vector<Parameter>& parameters,
                           Problem* problem, std::vector<double>* u, FitSummary* summary) {
  const int m = static_cast<int>(problem->Residuals(*u).size());
  ceres::Problem ceres_problem;
  ceres_problem.AddResidualBlock(new FiniteDifferenceCost(problem, m, static_cast<int>(u->size())),
                                 nullptr, u->data());
  for (std::size_t i = 0; i < u->size(); ++i) {
    if (problem->Lower(i) > -1e299)
      ceres_problem.SetParameterLowerBound(u->data(), int(i), problem->Lower(i));
    if (problem->Upper(i) < 1e299)
      ceres_problem.SetParameterUpperBound(u->data(), int(i), problem->Upper(i));
  }
  ceres::Solver::Options options;
  options.trust_region_strategy_type =
      o.solver == Solver::kDogleg ? ceres::DOGLEG : ceres::LEVENBERG_MARQUARDT;
  options.max_num_iterations = o.max_iterations;
  options.update_state_every_iteration = true;
  options.logging_type = ceres::SILENT;
  options.num_threads = 1;  // the finite-difference points already run in parallel
  HistoryCallback callback(problem, u->data(), u->size(), o, parameters, summary);
  options.callbacks.push_back(&callback);
  ceres::Solver::Summary ceres_summary;
  ceres::Solve(options, &ceres_problem, &ceres_summary);
  if (o.cancelled && o.cancelled()) return "cancelled";
  return ceres_summary.message;
}

bool SignFlipped(const std::vector<double>& a, const std::vector<double>& b) {
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i] * b[i] < 0) return true;
  return false;
}

std::string SolveWithGradientDescent(const FitOptions& o, Problem* problem, std::vector<double>* u,
                                     const std::vector<Parameter>& parameters,
                                     FitSummary* summary) {
  double rate = o.learning_rate;
  std::vector<double> previous_u;
  for (int k = 0; k < o.max_iterations; ++k) {
    std::vector<double> jacobian;
    try {
      problem->ResidualsAndJacobian(*u, &jacobian);
    } catch (const InputError&) {
      // The step left what the simulation takes (a constant made unphysical, a run gone
      // unstable): as Ceres does, a shorter one from the last point. The start is bad input.
      if (summary->iterations.empty()) throw;
      rate /= 2;
      for (std::size_t j = 0; j < u->size(); ++j)
        (*u)[j] = std::clamp(previous_u[j] - rate * summary->iterations.back().gradient[j],
                             problem->Lower(j), problem->Upper(j));
      continue;
    }
    Iteration it = problem->Record(k, *u, previous_u);
    const Iteration* last = summary->iterations.empty() ? nullptr : &summary->iterations.back();
    if (last && it.loss > last->loss && SignFlipped(it.gradient, last->gradient)) {
      rate /= 2;  // overshot the minimum: go back and take half the step
      for (std::size_t j = 0; j < u->size(); ++j)
        (*u)[j] = previous_u[j] - rate * last->gradient[j];
      continue;
    }
    summary->iterations.push_back(it);
    if (o.on_iteration) o.on_iteration(ToJson(o, parameters, *summary));
    if (it.loss < o.loss_threshold) return "loss below threshold";
    if (o.cancelled && o.cancelled()) return "cancelled";
    previous_u = *u;
    for (std::size_t j = 0; j < u->size(); ++j)
      (*u)[j] = std::clamp((*u)[j] - rate * it.gradient[j], problem->Lower(j), problem->Upper(j));
  }
  return "maximum iterations reached";
}

}  // namespace

Solver ParseSolver(const std::string& name) {
  if (name == "lm") return Solver::kLevenbergMarquardt;
  if (name == "dogleg") return Solver::kDogleg;
  if (name == "gd") return Solver::kGradientDescent;
  throw InputError("unknown solver '" + name + "': expected lm, dogleg or gd");
}

const char* SolverName(Solver s) {
  switch (s) {
    case Solver::kLevenbergMarquardt:
      return "levenberg_marquardt";
    case Solver::kDogleg:
      return "dogleg";
    case Solver::kGradientDescent:
      return "gradient_descent";
  }
  return "?";
}

void Fit(const FitOptions& o, const std::vector<Parameter>& parameters, const Objective& objective,
         FitSummary* summary) {
  if (parameters.empty()) throw InputError("fit: no parameter to fit");
  std::vector<double> start;
  for (const Parameter& p : parameters) {
    if (p.log_space && !(p.start > 0))
      throw InputError("fit: log-space parameter '" + p.name + "' must start positive");
    start.push_back(p.start);
  }
  Problem problem(o, parameters, objective);
  std::vector<double> u = problem.ToInternal(start);
  try {
    summary->stop_reason = o.solver == Solver::kGradientDescent
                               ? SolveWithGradientDescent(o, &problem, &u, parameters, summary)
                               : SolveWithCeres(o, parameters, &problem, &u, summary);
  } catch (const Cancelled&) {  // gradient descent: our own loop, no library in between
    summary->stop_reason = "cancelled";
  }
  if (!summary->iterations.empty()) {
    const Iteration& best =
        *std::min_element(summary->iterations.begin(), summary->iterations.end(),
                          [](const Iteration& a, const Iteration& b) { return a.loss < b.loss; });
    summary->final_values = best.values;
    summary->final_loss = best.loss;
  }
  summary->evaluations = problem.evaluations();
  summary->converged = !summary->iterations.empty() && summary->final_loss < o.loss_threshold;
  if (summary->converged)
    summary->stop_reason = "loss below threshold (" + summary->stop_reason + ")";
  summary->wall_s = problem.elapsed_s();
}

std::string FitSummary::BriefReport() const {
  std::ostringstream s;
  s << (converged ? "converged" : "not converged") << ": loss " << final_loss << " after "
    << iterations.size() << " iterations, " << evaluations << " evaluations, " << wall_s << " s ("
    << stop_reason << ")";
  return s.str();
}

nlohmann::json ToJson(const FitOptions& o, const std::vector<Parameter>& parameters,
                      const FitSummary& s, const nlohmann::json& targets) {
  auto named = [&](const std::vector<double>& values) {
    nlohmann::json j = nlohmann::json::object();
    for (std::size_t i = 0; i < values.size() && i < parameters.size(); ++i)
      j[parameters[i].name] = values[i];
    return j;
  };
  nlohmann::json params = nlohmann::json::array();
  for (const Parameter& p : parameters)
    params.push_back({{"name", p.name},
                      {"start", p.start},
                      {"log_space", p.log_space},
                      {"lower", p.lower},
                      {"upper", p.upper}});
  nlohmann::json iterations = nlohmann::json::array();
  for (const Iteration& it : s.iterations)
    iterations.push_back({{"iteration", it.iteration},
                          {"parameters", named(it.values)},
                          {"loss", it.loss},
                          {"residuals", it.residuals},
                          {"gradient", it.gradient},
                          {"step", it.step},
                          {"evaluations", it.evaluations},
                          {"wall_s", it.wall_s}});
  return {{"schema", kFitHistorySchema},
          {"solver", SolverName(o.solver)},
          {"loss_threshold", o.loss_threshold},
          {"parameters", params},
          {"targets", targets},
          {"iterations", iterations},
          {"final", {{"parameters", named(s.final_values)}, {"loss", s.final_loss}}},
          {"evaluations", s.evaluations},
          {"converged", s.converged},
          {"stop_reason", s.stop_reason},
          {"wall_s", s.wall_s}};
}

}  // namespace owval::sgd
