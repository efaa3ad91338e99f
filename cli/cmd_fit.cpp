// owval fit: phase 5, parameters fitted by an optimiser with the convergence history saved.
#include <atomic>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "command.hpp"
#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/progress.hpp"
#include "owval/reports/pipeline_report.hpp"
#include "owval/sgd/engine_simulator.hpp"
#include "owval/sgd/fit.hpp"
#include "owval/sgd/gradient_fit.hpp"
#include "owval/sgd/targets.hpp"
#include "resolve.hpp"

namespace owval::cli {
namespace {
namespace fs = std::filesystem;

std::atomic<bool> g_interrupted{false};
extern "C" void OnInterrupt(int) { g_interrupted = true; }

struct FitArgs {
  std::string config;
  std::vector<std::string> params, targets;
  TrackFlags track;
  double time_s = 0.05;
  int log_step = 1;
  std::string solver = "lm";
  std::string command;
  std::string out;
  double threshold = 1e-4;
  int max_iterations = 20;
  double learning_rate = 0.5;
  bool json = false;
  // --gradient analytic (XPBD's reverse pass)
  std::string gradient = "fd";
  std::string backend = "pcisph";
  std::string reference;
  std::vector<std::string> loss_groups;
  double loss_scale = 1;
  std::size_t checkpoint_every = 10, window = 0;
  double clip_norm = 0;
};

// The analytic fit: loss against a reference trajectory, gradient from the engine's reverse pass.
void RunGradientFit(const FitArgs& a) {
  if (a.reference.empty())
    throw InputError("fit --gradient analytic: --reference FILE (a trajectory) is required");
  if (!a.command.empty()) throw InputError("fit --gradient analytic: takes no --command");
  std::vector<sgd::Parameter> parameters;
  for (const std::string& p : a.params) parameters.push_back(sgd::ParseParameter(p));
  const fs::path out = a.out;
  fs::create_directories(out);
  const Trajectory reference = ReadTrajectoryArgument(a.reference);
  const engine::SiberneticConfig config = ResolveConfig(a.config);
  const engine::DifferentiableXpbd model(config, engine::PhysicsConstants{});
  sgd::GradientFitOptions options;
  options.loss_threshold = a.threshold;
  options.max_iterations = a.max_iterations;
  options.finite_differences = a.gradient == "model-fd";
  if (a.solver == "adam") {
    options.method = sgd::GradientFitOptions::Method::kAdam;
    options.learning_rate = a.learning_rate;
  } else if (a.solver != "lm" && a.solver != "lbfgs") {
    throw InputError("fit --gradient " + a.gradient + ": --solver is lbfgs (default) or adam");
  }
  options.reverse.steps =
      std::size_t(std::llround(a.time_s / engine::PhysicsConstants{}.time_step_s));
  options.reverse.checkpoint_every = a.checkpoint_every;
  options.reverse.window = a.window;
  options.reverse.clip_norm = a.clip_norm;
  std::vector<engine::LossTerm> loss;
  if (a.loss_groups.empty()) {
    loss = sgd::TrackLoss(reference, a.track.Over(Track{}), options.reverse.steps, a.loss_scale);
  } else {
    for (const std::string& g : a.loss_groups)
      for (engine::LossTerm& t :
           sgd::TrackLoss(reference, Track{0, g, Axis::kY}, options.reverse.steps, a.loss_scale,
                          /*every_axis=*/true))
        loss.push_back(std::move(t));
  }
  options.on_iteration = [&](const nlohmann::json& history) {
    WriteFileAtomically(out / "history.json", history.dump(2) + "\n");
    if (!QuietMode())
      std::fprintf(stderr, "fit: iteration %zu, loss %.3g\n", history["iterations"].size() - 1,
                   history["iterations"].back()["loss"].get<double>());
  };
  sgd::GradientFitSummary summary;
  sgd::FitWithGradient(options, model, parameters, loss, &summary);
  const nlohmann::json history = sgd::ToJson(options, parameters, summary);
  WriteFilesTogether({{out / "history.json", history.dump(2) + "\n"},
                      {out / "parameters.json", history["final"].dump(2) + "\n"},
                      {out / "convergence.svg", reports::ConvergencePlot(summary.fit)}});
  if (a.json) {
    std::cout << history.dump(2) << "\n";
  } else {
    std::cout << summary.fit.BriefReport() << ", " << summary.total_simulation_equivalents
              << " simulation-equivalents\n";
    for (std::size_t i = 0; i < parameters.size() && i < summary.fit.final_values.size(); ++i)
      std::cout << "  " << parameters[i].name << " = " << summary.fit.final_values[i] << "\n";
  }
  if (!summary.fit.converged) SetExitCode(kExitGateFailed);
}

void RunFit(const FitArgs& a) {
  if (a.gradient != "fd") return RunGradientFit(a);
  if (a.targets.empty()) throw InputError("fit: at least one --target is required");
  std::vector<sgd::Parameter> parameters;
  for (const std::string& p : a.params) parameters.push_back(sgd::ParseParameter(p));
  std::vector<sgd::Target> targets;
  for (const std::string& t : a.targets) targets.push_back(sgd::ParseTarget(t));
  const Track tracking = a.track.Over(Track{});
  const fs::path out = a.out;
  fs::create_directories(out);
  sgd::Simulator simulator;
  if (!a.command.empty()) {
    simulator = sgd::CommandSimulator(a.command, parameters, out / "evaluations");
  } else {
    engine::RunOptions run;
    run.duration_s = a.time_s;
    run.log_step = a.log_step;
    run.backend = a.backend;
    simulator = sgd::EngineSimulator(ResolveConfig(a.config), run, parameters);
  }
  sgd::FitOptions options;
  options.solver = sgd::ParseSolver(a.solver);
  options.loss_threshold = a.threshold;
  options.max_iterations = a.max_iterations;
  options.learning_rate = a.learning_rate;
  const nlohmann::json targets_json = sgd::TargetsToJson(targets, tracking);
  options.on_iteration = [&](const nlohmann::json& history) {
    nlohmann::json h = history;
    h["targets"] = targets_json;
    WriteFileAtomically(out / "history.json", h.dump(2) + "\n");
    if (!QuietMode())
      std::fprintf(stderr, "fit: iteration %zu, loss %.3g\n", h["iterations"].size() - 1,
                   h["iterations"].back()["loss"].get<double>());
  };
  g_interrupted = false;
  options.cancelled = [] { return g_interrupted.load(); };
  const auto previous = std::signal(SIGINT, OnInterrupt);
  sgd::FitSummary summary;
  sgd::Fit(options, parameters, sgd::MakeObjective(simulator, tracking, targets), &summary);
  std::signal(SIGINT, previous);
  const nlohmann::json history = sgd::ToJson(options, parameters, summary, targets_json);
  WriteFilesTogether({{out / "history.json", history.dump(2) + "\n"},
                      {out / "parameters.json", history["final"].dump(2) + "\n"},
                      {out / "convergence.svg", reports::ConvergencePlot(summary)}});
  if (a.json) {
    std::cout << history.dump(2) << "\n";
  } else {
    std::cout << summary.BriefReport() << "\n";
    for (std::size_t i = 0; i < parameters.size() && i < summary.final_values.size(); ++i)
      std::cout << "  " << parameters[i].name << " = " << summary.final_values[i] << "\n";
  }
  if (!summary.converged) SetExitCode(kExitGateFailed);
}

void SetUp(CLI::App& app) {
  auto a = std::make_shared<FitArgs>();
  CLI::App* cmd = app.add_subcommand(
      "fit", "Phase 5: fit parameters with Ceres (or gradient descent), history saved");
  cmd->add_option("config", a->config,
                  "Scenario name or Sibernetic configuration (unused with --command)")
      ->required();
  cmd->add_option("--param", a->params,
                  "NAME=START[:log|:lin][:LOWER:UPPER], e.g. elasticity_coefficient=1.62e8:log")
      ->required();
  cmd->add_option("--target", a->targets,
                  "METRIC=VALUE[:scale=S][:weight=W][:ref=FILE]; METRIC: period, "
                  "half_amplitude, equilibrium, rms (finite-difference fits)");
  AddTrackFlags(cmd, &a->track, "track-", "Tracked");
  cmd->add_option("--time", a->time_s, "Simulated time per evaluation (s)");
  cmd->add_option("--log-step", a->log_step, "Steps between frames");
  cmd->add_option("--solver", a->solver,
                  "lm, dogleg or gd; with --gradient analytic|model-fd: lbfgs (default) or adam")
      ->check(CLI::IsMember({"lm", "dogleg", "gd", "lbfgs", "adam"}));
  cmd->add_option("--command", a->command,
                  "External simulator: {param} placeholders, {out} dir, {out_file}");
  cmd->add_option("--threshold", a->threshold, "Stop when the loss is below this (default 1e-4)");
  cmd->add_option("--max-iterations", a->max_iterations, "Iteration cap");
  cmd->add_option("--learning-rate", a->learning_rate, "Gradient descent step in internal units");
  cmd->add_option("-o,--out", a->out,
                  "Output directory (history.json, parameters.json, convergence.svg)")
      ->required();
  cmd->add_flag("--json", a->json, "Print the history as JSON");
  cmd->add_option("--backend", a->backend,
                  "Engine scheme of the finite-difference fit's simulations (pcisph, xpbd)");
  cmd->add_option("--gradient", a->gradient,
                  "fd (finite differences of runs, any backend), analytic (XPBD's reverse "
                  "pass, Ceres L-BFGS) or model-fd (the same L-BFGS and model, central "
                  "differences instead of the reverse pass: the comparison run)")
      ->check(CLI::IsMember({"fd", "analytic", "model-fd"}));
  cmd->add_option("--reference", a->reference,
                  "analytic: trajectory the loss compares with (frames paired by step)");
  cmd->add_option("--loss-group", a->loss_groups,
                  "analytic: group centroids (all axes) in the loss instead of the tracked "
                  "coordinate; repeatable");
  cmd->add_option("--loss-scale", a->loss_scale, "analytic: length scale of the loss (cu)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--checkpoint-every", a->checkpoint_every,
                  "analytic: states kept every k steps (0: full tape)");
  cmd->add_option("--window", a->window, "analytic: truncated backpropagation window (steps)");
  cmd->add_option("--clip-norm", a->clip_norm, "analytic: per-step state-gradient norm clip");
  cmd->callback([a] { RunFit(*a); });
}

const bool registered = RegisterCommand(&SetUp);

}  // namespace
}  // namespace owval::cli
