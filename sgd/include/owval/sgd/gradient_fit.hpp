#pragma once
// `owval fit --gradient analytic` (issue 14): the XPBD substrate's parameters fitted by Ceres'
// GradientProblem (L-BFGS line search) on a trajectory loss whose gradient comes from the
// engine's reverse pass (owval/engine/gradient.hpp), not from finite differences. Positive
// parameters are optimised in log space (DD001's rule for stiffness-like values). The history
// has fit.hpp's schema (docs/fit_history.md) plus per iteration "gradient_norm" and
// "simulation_equivalents" (forward + reverse wall time in units of one forward simulation,
// cumulative), so it compares with a finite-difference fit's "evaluations".
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "owval/engine/gradient.hpp"
#include "owval/sgd/fit.hpp"
#include "owval/sgd/targets.hpp"
#include "owval/trajectory/frame_source.hpp"

namespace owval::sgd {

struct GradientFitOptions {
  // kLbfgs: Ceres' GradientProblem with an L-BFGS line search. kAdam: DD001's rules, Adam
  // (learning_rate in internal coordinates) on log-space parameters, sign steps halved on a
  // sign flip and clamped to the bounds on linear ones; one evaluation per iteration.
  enum class Method { kLbfgs, kAdam } method = Method::kLbfgs;
  double learning_rate = 0.05;
  double loss_threshold = 1e-4;
  int max_iterations = 20;
  // kAdam: the fit ends as stalled once `patience` iterations in a row have not lowered the best
  // loss by a relative `min_improvement` (0: never); its result is the best iterate, not the
  // last (Adam's steps do not shrink, so it wanders around a minimum, and a truncated gradient
  // (reverse.window) can lead it back uphill).
  int patience = 10;
  double min_improvement = 1e-3;
  engine::GradientOptions reverse;  // steps, checkpointing, window, clipping
  // The comparison run: the same model, loss and L-BFGS, the gradient by central differences
  // (2 forward simulations per parameter, step `fd_step` in internal coordinates) instead of
  // the reverse pass.
  bool finite_differences = false;
  double fd_step = 1e-4;
  std::function<void(const nlohmann::json& history)> on_iteration;
  // Polled after each iteration: true ends the fit with stop reason "cancelled", its history
  // and best iterate kept.
  std::function<bool()> cancelled;
};

struct GradientFitSummary {
  FitSummary fit;                              // iterations, final values, loss, stop reason
  std::vector<double> gradient_norm;           // per iteration, internal coordinates
  std::vector<double> simulation_equivalents;  // per iteration, cumulative
  double total_simulation_equivalents = 0;     // the residuals' forward runs included
};

// Parameter names: GradientParameterNames(), or "elasticity_coefficient" (both bond types, the
// non-worm-body one at the constants' non_worm_body_spring_factor, as the run derives them).
// Throws InputError for any other name.
void FitWithGradient(const GradientFitOptions& options, const engine::DifferentiableXpbd& model,
                     const std::vector<Parameter>& parameters,
                     const std::vector<engine::LossTerm>& loss, GradientFitSummary* summary);

// The loss's terms at `values` (the parameters' own units), as FitWithGradient records an
// iteration's residuals (Σ r² = its loss): what the PR checklist reruns at the best iterate.
std::vector<double> GradientFitResiduals(const engine::DifferentiableXpbd& model,
                                         const std::vector<Parameter>& parameters,
                                         const std::vector<double>& values,
                                         const std::vector<engine::LossTerm>& loss,
                                         std::size_t steps);

nlohmann::json ToJson(const GradientFitOptions& options, const std::vector<Parameter>& parameters,
                      const GradientFitSummary& summary);

// The loss of a fit against a trajectory: the tracked particle's (or group centroid's) axis
// coordinate (every axis when every_axis) at every frame of `reference` up to `steps`,
// frames paired by step index (frame f, f ≥ 1, is the model's state after f·log_step steps: a
// run records frame 0 after its first step, which moves nothing), each squared difference
// divided by scale² and by the number of frames. The reference is read frame by frame, up to
// `steps` only; the loss keeps one position a frame. InputError when the track names nothing in
// the reference.
std::vector<engine::LossTerm> TrackLoss(FrameSource& reference, const Track& tracking,
                                        std::size_t steps, double scale, bool every_axis = false);

// TrackLoss of each group's centroid, every axis (demo1's fit loss: {"elastic", "liquid"}), in
// one pass over the reference.
std::vector<engine::LossTerm> GroupCentroidLoss(FrameSource& reference,
                                                const std::vector<std::string>& groups,
                                                std::size_t steps, double scale);

// DD001's oscillator loss through a differentiable surrogate: the tracked coordinate against
// y(t) = equilibrium + (start − equilibrium)·cos(2πt/period) at every step up to `steps`
// (half-amplitude |start − equilibrium|), normalised as TrackLoss. Zero exactly when the
// trajectory is that undamped oscillation released from rest at `start` (one_sprig's start);
// the zero-crossing period and the peak-to-peak amplitude themselves are not differentiable.
std::vector<engine::LossTerm> OscillatorLoss(std::int32_t particle, int axis, double period_s,
                                             double equilibrium, double start, double time_step_s,
                                             std::size_t steps, double scale);

}  // namespace owval::sgd
