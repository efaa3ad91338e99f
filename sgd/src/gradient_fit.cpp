#include "owval/sgd/gradient_fit.hpp"

#include <ceres/ceres.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

#include "owval/base/errors.hpp"
#include "owval/engine/config.hpp"

namespace owval::sgd {
namespace {

using Clock = std::chrono::steady_clock;

// Which model parameters a fitted parameter moves, and by what factor of its value.
struct Mapping {
  std::vector<std::pair<std::size_t, double>> targets;
};

Mapping MappingOf(const std::string& name) {
  const std::vector<std::string>& names = engine::GradientParameterNames();
  if (name == "elasticity_coefficient")
    return {{{1, 1.0}, {2, engine::PhysicsConstants{}.non_worm_body_spring_factor}}};
  const auto it = std::find(names.begin(), names.end(), name);
  if (it == names.end()) {
    std::string known = "elasticity_coefficient";
    for (const std::string& n : names) known += ", " + n;
    throw InputError("fit --gradient analytic: unknown parameter '" + name + "': expected one of " +
                     known);
  }
  return {{{std::size_t(it - names.begin()), 1.0}}};
}

// The loss and its gradient in internal coordinates (log for log-space parameters).
class Function final : public ceres::FirstOrderFunction {
 public:
  Function(const engine::DifferentiableXpbd& model, const std::vector<Parameter>& parameters,
           const std::vector<engine::LossTerm>& loss, const GradientFitOptions& o,
           GradientFitSummary* summary)
      : model_(model),
        parameters_(parameters),
        loss_(loss),
        reverse_(o.reverse),
        finite_differences_(o.finite_differences),
        fd_step_(o.fd_step),
        summary_(*summary),
        base_(model.DefaultParameters()) {
    for (const Parameter& p : parameters) mappings_.push_back(MappingOf(p.name));
  }
  int NumParameters() const override { return int(parameters_.size()); }

  std::vector<double> Values(const double* u) const {
    std::vector<double> x(parameters_.size());
    for (std::size_t i = 0; i < x.size(); ++i)
      x[i] = parameters_[i].log_space ? std::exp(u[i]) : u[i];
    return x;
  }

  std::vector<double> Theta(const std::vector<double>& x) const {
    std::vector<double> theta = base_;
    for (std::size_t i = 0; i < x.size(); ++i)
      for (const auto& [index, factor] : mappings_[i].targets) theta[index] = factor * x[i];
    return theta;
  }

  // Central differences through the same model: 1 + 2n forward simulations.
  bool EvaluateByDifferences(const double* u, double* cost, double* gradient) const {
    const std::size_t n = parameters_.size();
    *cost = model_.Loss(Theta(Values(u)), loss_, reverse_.steps);
    ++summary_.fit.evaluations;
    summary_.total_simulation_equivalents += 1;
    last_gradient_.assign(n, 0);
    if (gradient) {
      // The 2n shifted simulations are independent (the model is const): one per thread.
      std::vector<double> shifted(2 * n);
#pragma omp parallel for schedule(dynamic)
      for (std::size_t k = 0; k < 2 * n; ++k) {
        std::vector<double> at(u, u + n);
        at[k / 2] += k % 2 == 0 ? fd_step_ : -fd_step_;
        shifted[k] = model_.Loss(Theta(Values(at.data())), loss_, reverse_.steps);
      }
      for (std::size_t i = 0; i < n; ++i)
        gradient[i] = last_gradient_[i] = (shifted[2 * i] - shifted[2 * i + 1]) / (2 * fd_step_);
      summary_.total_simulation_equivalents += 2.0 * double(n);
    }
    if (!std::isfinite(*cost)) return false;
    last_cost_ = *cost;
    return true;
  }

  bool Evaluate(const double* u, double* cost, double* gradient) const override {
    if (finite_differences_) return EvaluateByDifferences(u, cost, gradient);
    const std::vector<double> x = Values(u);
    const std::vector<double> theta = Theta(x);
    const engine::GradientSummary g = model_.Gradient(theta, loss_, reverse_);
    ++summary_.fit.evaluations;
    // One forward simulation is forward_seconds·steps/forward_steps; the evaluation cost all.
    const double one = g.forward_seconds * double(reverse_.steps) / double(g.forward_steps);
    summary_.total_simulation_equivalents +=
        gradient ? (g.forward_seconds + g.backward_seconds) / std::max(one, 1e-12) : 1.0;
    *cost = g.loss;
    last_gradient_.assign(x.size(), 0);
    for (std::size_t i = 0; i < x.size(); ++i) {
      double d = 0;
      for (const auto& [index, factor] : mappings_[i].targets)
        d += factor * g.parameter_gradient[index];
      last_gradient_[i] = parameters_[i].log_space ? d * x[i] : d;
      if (gradient) gradient[i] = last_gradient_[i];
    }
    if (!std::isfinite(*cost)) return false;
    last_cost_ = *cost;
    return true;
  }

  // The loss's terms at u as residuals (Σ r² = its loss, for the PR checklist to recompute;
  // docs/fit_history.md), from one more forward run, counted as one simulation.
  std::vector<double> Residuals(const double* u) const {
    std::vector<double> r;
    model_.Loss(Theta(Values(u)), loss_, reverse_.steps, &r);
    summary_.total_simulation_equivalents += 1;
    return r;
  }

  double last_cost() const { return last_cost_; }
  const std::vector<double>& last_gradient() const { return last_gradient_; }

 private:
  const engine::DifferentiableXpbd& model_;
  const std::vector<Parameter>& parameters_;
  const std::vector<engine::LossTerm>& loss_;
  const engine::GradientOptions& reverse_;
  bool finite_differences_;
  double fd_step_;
  GradientFitSummary& summary_;
  std::vector<double> base_;
  std::vector<Mapping> mappings_;
  mutable std::vector<double> last_gradient_;
  mutable double last_cost_ = 0;
};

class History final : public ceres::IterationCallback {
 public:
  History(const Function& f, const double* u, const GradientFitOptions& o,
          const std::vector<Parameter>& parameters, GradientFitSummary* s)
      : f_(f), u_(u), o_(o), parameters_(parameters), s_(*s), start_(Clock::now()) {}

  ceres::CallbackReturnType operator()(const ceres::IterationSummary& summary) override {
    Iteration it;
    it.iteration = int(summary.iteration);
    it.values = f_.Values(u_);
    it.loss = summary.cost;
    it.residuals = f_.Residuals(u_);
    it.gradient = f_.last_gradient();
    it.evaluations = s_.fit.evaluations;
    it.wall_s = std::chrono::duration<double>(Clock::now() - start_).count();
    s_.fit.iterations.push_back(it);
    s_.gradient_norm.push_back(summary.gradient_norm);
    s_.simulation_equivalents.push_back(s_.total_simulation_equivalents);
    if (o_.on_iteration) o_.on_iteration(ToJson(o_, parameters_, s_));
    if (summary.cost < o_.loss_threshold) return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
    return o_.cancelled && o_.cancelled() ? ceres::SOLVER_ABORT : ceres::SOLVER_CONTINUE;
  }

 private:
  const Function& f_;
  const double* u_;
  const GradientFitOptions& o_;
  const std::vector<Parameter>& parameters_;
  GradientFitSummary& s_;
  Clock::time_point start_;
};

// DD001's rules: Adam on log-space (positive, stiffness-like) parameters; a bounded linear
// parameter moves by its own step against the gradient's sign, the step halved whenever that
// sign flips, clamped into [lower, upper].
void FitWithAdam(const GradientFitOptions& o, const engine::DifferentiableXpbd& model,
                 const std::vector<Parameter>& parameters,
                 const std::vector<engine::LossTerm>& loss, std::vector<double> u,
                 GradientFitSummary* summary) {
  const auto start = Clock::now();
  Function f(model, parameters, loss, o, summary);
  const std::size_t n = u.size();
  std::vector<double> m(n, 0), v(n, 0), g(n), step(n), last_sign(n, 0);
  for (std::size_t i = 0; i < n; ++i) step[i] = o.learning_rate * std::max(std::abs(u[i]), 1.0);
  FitSummary& fit = summary->fit;
  double cost = 0;
  std::size_t best = 0;  // the best iterate's index in fit.iterations
  int stalled = 0;       // iterations since the best loss last improved by min_improvement
  for (int it = 0; it <= o.max_iterations; ++it) {
    if (!f.Evaluate(u.data(), &cost, g.data()))
      throw InputError("fit: the loss is not finite at iteration " + std::to_string(it));
    double norm = 0;
    for (double x : g) norm += x * x;
    Iteration record;
    record.iteration = it;
    record.values = f.Values(u.data());
    record.loss = cost;
    record.residuals = f.Residuals(u.data());
    record.gradient = g;
    record.evaluations = fit.evaluations;
    record.wall_s = std::chrono::duration<double>(Clock::now() - start).count();
    fit.iterations.push_back(std::move(record));
    summary->gradient_norm.push_back(std::sqrt(norm));
    summary->simulation_equivalents.push_back(summary->total_simulation_equivalents);
    if (o.on_iteration) o.on_iteration(ToJson(o, parameters, *summary));
    const double best_loss = fit.iterations[best].loss;
    stalled = it > 0 && !(cost < best_loss * (1 - o.min_improvement)) ? stalled + 1 : 0;
    if (cost < best_loss) best = fit.iterations.size() - 1;
    if (cost < o.loss_threshold || it == o.max_iterations) break;
    if (o.cancelled && o.cancelled()) {
      fit.stop_reason = "cancelled";
      break;
    }
    if (o.patience > 0 && stalled >= o.patience) {
      fit.stop_reason = "stalled: the best loss fell by less than " +
                        std::to_string(o.min_improvement) + " (relative) in " +
                        std::to_string(o.patience) + " iterations";
      break;
    }
    for (std::size_t i = 0; i < n; ++i) {
      const Parameter& p = parameters[i];
      if (p.log_space) {
        m[i] = 0.9 * m[i] + 0.1 * g[i];
        v[i] = 0.999 * v[i] + 0.001 * g[i] * g[i];
        const double mh = m[i] / (1 - std::pow(0.9, it + 1)),
                     vh = v[i] / (1 - std::pow(0.999, it + 1));
        u[i] -= o.learning_rate * mh / (std::sqrt(vh) + 1e-12);
        continue;
      }
      const double sign = g[i] > 0 ? 1.0 : g[i] < 0 ? -1.0 : 0.0;
      if (sign != 0 && last_sign[i] != 0 && sign != last_sign[i]) step[i] /= 2;
      if (sign != 0) last_sign[i] = sign;
      u[i] = std::clamp(u[i] - sign * step[i], p.lower, p.upper);
    }
  }
  fit.final_values = fit.iterations[best].values;
  fit.final_loss = fit.iterations[best].loss;
  fit.converged = fit.final_loss < o.loss_threshold;
  if (fit.converged) fit.stop_reason = "loss below threshold";
  if (fit.stop_reason.empty()) fit.stop_reason = "maximum iterations reached";
  if (best + 1 != fit.iterations.size())
    fit.stop_reason += "; result: the best iterate, " + std::to_string(best);
  fit.wall_s = std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace

void FitWithGradient(const GradientFitOptions& o, const engine::DifferentiableXpbd& model,
                     const std::vector<Parameter>& parameters,
                     const std::vector<engine::LossTerm>& loss, GradientFitSummary* summary) {
  *summary = {};
  const auto start = Clock::now();
  std::vector<double> u;
  for (const Parameter& p : parameters) {
    if (p.log_space && !(p.start > 0))
      throw InputError("fit: log-space parameter " + p.name + " needs a positive start");
    u.push_back(p.log_space ? std::log(p.start) : p.start);
  }
  if (o.method == GradientFitOptions::Method::kAdam)
    return FitWithAdam(o, model, parameters, loss, u, summary);
  auto* function = new Function(model, parameters, loss, o, summary);
  ceres::GradientProblem problem(function);  // takes ownership
  ceres::GradientProblemSolver::Options options;
  options.line_search_direction_type = ceres::LBFGS;
  options.max_num_iterations = o.max_iterations;
  options.update_state_every_iteration = true;
  options.logging_type = ceres::SILENT;
  options.function_tolerance = 1e-12;
  options.gradient_tolerance = 1e-14;
  options.parameter_tolerance = 1e-12;
  History history(*function, u.data(), o, parameters, summary);
  options.callbacks.push_back(&history);
  ceres::GradientProblemSolver::Summary s;
  ceres::Solve(options, problem, u.data(), &s);
  FitSummary& fit = summary->fit;
  // Cancelled (SOLVER_ABORT): Ceres leaves final_cost unset; u is the last iteration's state.
  const bool cancelled = s.termination_type == ceres::USER_FAILURE && !fit.iterations.empty();
  fit.final_values = function->Values(u.data());
  fit.final_loss = cancelled ? fit.iterations.back().loss : s.final_cost;
  fit.converged = fit.final_loss < o.loss_threshold;
  fit.stop_reason = fit.converged ? "loss below threshold" : cancelled ? "cancelled" : s.message;
  fit.wall_s = std::chrono::duration<double>(Clock::now() - start).count();
}

std::vector<double> GradientFitResiduals(const engine::DifferentiableXpbd& model,
                                         const std::vector<Parameter>& parameters,
                                         const std::vector<double>& values,
                                         const std::vector<engine::LossTerm>& loss,
                                         std::size_t steps) {
  GradientFitOptions options;
  options.reverse.steps = steps;
  GradientFitSummary unused;
  const Function f(model, parameters, loss, options, &unused);  // its parameter mapping
  std::vector<double> r;
  model.Loss(f.Theta(values), loss, steps, &r);
  return r;
}

nlohmann::json ToJson(const GradientFitOptions& o, const std::vector<Parameter>& parameters,
                      const GradientFitSummary& s) {
  FitOptions fit;
  fit.solver = Solver::kGradientDescent;
  fit.loss_threshold = o.loss_threshold;
  fit.max_iterations = o.max_iterations;
  nlohmann::json j = ToJson(fit, parameters, s.fit);
  j["solver"] = o.method == GradientFitOptions::Method::kAdam ? "adam" : "lbfgs";
  j["gradient"] = o.finite_differences ? "model_finite_differences" : "analytic";
  j["reverse"] = {{"steps", o.reverse.steps},
                  {"checkpoint_every", o.reverse.checkpoint_every},
                  {"window", o.reverse.window},
                  {"clip_norm", o.reverse.clip_norm}};
  for (std::size_t i = 0; i < j["iterations"].size() && i < s.gradient_norm.size(); ++i) {
    j["iterations"][i]["gradient_norm"] = s.gradient_norm[i];
    j["iterations"][i]["simulation_equivalents"] = s.simulation_equivalents[i];
  }
  j["simulation_equivalents"] = s.total_simulation_equivalents;
  return j;
}

namespace {

// A loss term's particles and axes, its frames not yet filled.
engine::LossTerm TermOf(const Trajectory& header, const Track& tracking, bool every_axis) {
  tracking.Validate(header);
  engine::LossTerm term;
  if (tracking.group.empty()) {
    term.target = engine::LossTerm::Target::kParticle;
    term.particles = {std::int32_t(tracking.particle)};
  } else {
    term.target = engine::LossTerm::Target::kCentroid;
    for (std::size_t i : GroupIndices(header, tracking.group))
      term.particles.push_back(std::int32_t(i));
  }
  if (!every_axis) {
    term.axis_weight = {0, 0, 0};
    term.axis_weight[std::size_t(tracking.axis)] = 1;
  }
  return term;
}

// One term per track, their targets read in one pass over the reference's frames: the mean of
// the term's particles at each frame within `steps`, one Vec3d a frame (never the frames).
std::vector<engine::LossTerm> TrackLosses(FrameSource& reference, const std::vector<Track>& tracks,
                                          std::size_t steps, double scale, bool every_axis) {
  const Trajectory& header = reference.header();
  std::vector<engine::LossTerm> terms;
  for (const Track& t : tracks) terms.push_back(TermOf(header, t, every_axis));
  const std::size_t log_step = std::size_t(std::max(header.log_step, 1));
  // A run records frame 0 after its first step, which moves nothing (as Sibernetic's), so
  // frame f is the model's state after f·log_step steps from the configuration.
  for (std::size_t f = 1; f < reference.frame_count() && f * log_step <= steps; ++f) {
    const FrameRef frame = reference.Frame(f);
    for (engine::LossTerm& term : terms) {
      engine::Vec3d c{0, 0, 0};
      for (std::int32_t i : term.particles)
        for (int a = 0; a < 3; ++a)
          c[a] += frame.trajectory.coordinate(frame.frame, std::size_t(i), a);
      for (double& v : c) v /= double(term.particles.size());
      term.frame_steps.push_back(f * log_step);
      term.reference.push_back({c});
    }
  }
  for (engine::LossTerm& term : terms) {
    if (term.frame_steps.empty())
      throw InputError("fit: the reference has no frame within the fitted steps");
    term.weight = 1.0 / (scale * scale * double(term.frame_steps.size()));
  }
  return terms;
}

std::vector<Track> CentroidTracks(const std::vector<std::string>& groups) {
  std::vector<Track> tracks;
  for (const std::string& g : groups) tracks.push_back(Track{0, g, Axis::kY});
  return tracks;
}

}  // namespace

std::vector<engine::LossTerm> TrackLoss(FrameSource& reference, const Track& tracking,
                                        std::size_t steps, double scale, bool every_axis) {
  return TrackLosses(reference, {tracking}, steps, scale, every_axis);
}

std::vector<engine::LossTerm> GroupCentroidLoss(FrameSource& reference,
                                                const std::vector<std::string>& groups,
                                                std::size_t steps, double scale) {
  return TrackLosses(reference, CentroidTracks(groups), steps, scale, /*every_axis=*/true);
}

std::vector<engine::LossTerm> OscillatorLoss(std::int32_t particle, int axis, double period_s,
                                             double equilibrium, double start, double time_step_s,
                                             std::size_t steps, double scale) {
  engine::LossTerm term;
  term.particles = {particle};
  term.axis_weight = {0, 0, 0};
  term.axis_weight[std::size_t(axis)] = 1;
  for (std::size_t t = 1; t <= steps; ++t) {
    engine::Vec3d y{0, 0, 0};
    y[std::size_t(axis)] =
        equilibrium +
        (start - equilibrium) * std::cos(2 * std::numbers::pi * double(t) * time_step_s / period_s);
    term.frame_steps.push_back(t);
    term.reference.push_back({y});
  }
  term.weight = 1.0 / (scale * scale * double(steps));
  return {term};
}

}  // namespace owval::sgd
