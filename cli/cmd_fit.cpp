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
  std::size_t particle = 0;
  std::string group;
  std::string axis = "y";
  double time_s = 0.05;
  int log_step = 1;
  std::string solver = "lm";
  std::string command;
  std::string out;
  double threshold = 1e-4;
  int max_iterations = 20;
  double learning_rate = 0.5;
  bool json = false;
};

void RunFit(const FitArgs& a) {
  std::vector<sgd::Parameter> parameters;
  for (const std::string& p : a.params) parameters.push_back(sgd::ParseParameter(p));
  std::vector<sgd::Target> targets;
  for (const std::string& t : a.targets) targets.push_back(sgd::ParseTarget(t));
  Track tracking;
  tracking.particle = a.particle;
  tracking.group = a.group;
  tracking.axis = ParseAxisName(a.axis);
  const fs::path out = a.out;
  fs::create_directories(out);
  sgd::Simulator simulator;
  if (!a.command.empty()) {
    simulator = sgd::CommandSimulator(a.command, parameters, out / "evaluations");
  } else {
    engine::RunOptions run;
    run.duration_s = a.time_s;
    run.log_step = a.log_step;
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
  WriteFileAtomically(out / "history.json", history.dump(2) + "\n");
  WriteFileAtomically(out / "parameters.json", history["final"].dump(2) + "\n");
  WriteFileAtomically(out / "convergence.svg", reports::ConvergencePlot(summary));
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
                  "half_amplitude, equilibrium, rms")
      ->required();
  cmd->add_option("--track-particle", a->particle, "Tracked particle (default 0)")
      ->check(ParticleIndex());
  cmd->add_option("--track-group", a->group,
                  "Track a group centroid instead: elastic, liquid, all");
  cmd->add_option("--track-axis", a->axis, "x, y or z")->check(CLI::IsMember({"x", "y", "z"}));
  cmd->add_option("--time", a->time_s, "Simulated time per evaluation (s)");
  cmd->add_option("--log-step", a->log_step, "Steps between frames");
  cmd->add_option("--solver", a->solver, "lm, dogleg or gd")
      ->check(CLI::IsMember({"lm", "dogleg", "gd"}));
  cmd->add_option("--command", a->command,
                  "External simulator: {param} placeholders, {out} dir, {out_file}");
  cmd->add_option("--threshold", a->threshold, "Stop when the loss is below this (default 1e-4)");
  cmd->add_option("--max-iterations", a->max_iterations, "Iteration cap");
  cmd->add_option("--learning-rate", a->learning_rate, "Gradient descent step in internal units");
  cmd->add_option("-o,--out", a->out,
                  "Output directory (history.json, parameters.json, convergence.svg)")
      ->required();
  cmd->add_flag("--json", a->json, "Print the history as JSON");
  cmd->callback([a] { RunFit(*a); });
}

const bool registered = RegisterCommand(&SetUp);

}  // namespace
}  // namespace owval::cli
