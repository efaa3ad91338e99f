#include "owval/pipeline/fit_directory.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "owval/backends/registry.hpp"
#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/format.hpp"
#include "owval/engine/constants.hpp"
#include "owval/reports/pipeline_report.hpp"
#include "owval/scenarios/scenario.hpp"
#include "owval/sgd/backend_simulator.hpp"
#include "owval/sgd/engine_simulator.hpp"
#include "owval/sgd/fit.hpp"
#include "owval/sgd/fit_record.hpp"
#include "owval/sgd/gradient_fit.hpp"
#include "owval/sgd/targets.hpp"
#include "owval/trajectory/formats.hpp"

namespace owval::pipeline {
namespace {
namespace fs = std::filesystem;

std::vector<sgd::Parameter> ParametersOf(const FitRequest& r) {
  std::vector<sgd::Parameter> parameters;
  for (const std::string& p : r.parameters) parameters.push_back(sgd::ParseParameter(p));
  return parameters;
}

// history.json after an iteration, with a progress line.
void WriteProgress(const fs::path& out, const nlohmann::json& history, bool quiet) {
  WriteFileAtomically(out / "history.json", history.dump(2) + "\n");
  if (!quiet)
    std::fprintf(stderr, "fit: iteration %zu, loss %.3g\n", history["iterations"].size() - 1,
                 history["iterations"].back()["loss"].get<double>());
}

void WriteResults(const fs::path& out, const nlohmann::json& history, const std::string& svg) {
  WriteFilesTogether({{out / "history.json", history.dump(2) + "\n"},
                      {out / "parameters.json", history["final"].dump(2) + "\n"},
                      {out / "convergence.svg", svg}});
}

void Summarise(const std::vector<sgd::Parameter>& parameters, const sgd::FitSummary& fit,
               nlohmann::json history, FitDirectorySummary* summary) {
  summary->history = std::move(history);
  summary->converged = fit.converged;
  for (std::size_t i = 0; i < parameters.size() && i < fit.final_values.size(); ++i)
    summary->values.emplace_back(parameters[i].name, fit.final_values[i]);
}

// history.json's "simulation", made (and the configuration written beside the history) when the
// first history is written: a fit refused on its first evaluation leaves no configuration.txt.
class SimulationRecord {
 public:
  explicit SimulationRecord(std::function<nlohmann::json()> make) : make_(std::move(make)) {}
  nlohmann::json With(nlohmann::json history) {
    if (made_.is_null()) made_ = make_();
    history["simulation"] = made_;
    return history;
  }

 private:
  std::function<nlohmann::json()> make_;
  nlohmann::json made_;
};

std::vector<engine::LossTerm> LossOf(const FitRequest& r, FrameSource& reference,
                                     std::size_t steps) {
  if (r.loss_groups.empty()) return sgd::TrackLoss(reference, r.track, steps, r.loss_scale);
  return sgd::GroupCentroidLoss(reference, r.loss_groups, steps, r.loss_scale);
}

sgd::GradientFitOptions GradientOptions(const FitRequest& r) {
  sgd::GradientFitOptions options;
  options.loss_threshold = r.threshold;
  options.max_iterations = r.max_iterations;
  options.finite_differences = r.gradient == "model-fd";
  if (r.solver == "adam") {
    options.method = sgd::GradientFitOptions::Method::kAdam;
    options.learning_rate = r.learning_rate;
    options.patience = r.patience;
  } else if (r.solver != "lm" && r.solver != "lbfgs") {
    throw InputError("fit --gradient " + r.gradient + ": --solver is lbfgs (default) or adam");
  }
  options.reverse.steps =
      std::size_t(std::llround(r.time_s / engine::PhysicsConstants{}.time_step_s));
  options.reverse.checkpoint_every = r.checkpoint_every;
  options.reverse.window = r.window;
  options.reverse.clip_norm = r.clip_norm;
  return options;
}

// The analytic fit: loss against a reference trajectory, gradient from the engine's reverse pass.
void GradientFit(const FitRequest& r, const engine::SiberneticConfig& config,
                 FrameSource& reference, const std::function<bool()>& cancelled,
                 FitDirectorySummary* summary) {
  const std::vector<sgd::Parameter> parameters = ParametersOf(r);
  sgd::GradientFitOptions options = GradientOptions(r);
  const std::vector<engine::LossTerm> loss = LossOf(r, reference, options.reverse.steps);
  const fs::path out = r.out;
  CreateOutputDirectories(out);
  const engine::DifferentiableXpbd model(config, engine::PhysicsConstants{});
  if (r.reference_file.empty())
    throw InputError("fit --gradient " + r.gradient +
                     ": the reference's file is required (recorded for the rerun)");
  SimulationRecord simulation([&] {
    return sgd::ModelSimulationJson(sgd::RecordConfiguration(config, out), options.reverse.steps,
                                    r.reference_file, r.track, r.loss_groups, r.loss_scale);
  });
  options.on_iteration = [&](const nlohmann::json& h) {
    WriteProgress(out, simulation.With(h), r.quiet);
  };
  options.cancelled = cancelled;
  sgd::GradientFitSummary fit;
  sgd::FitWithGradient(options, model, parameters, loss, &fit);
  const nlohmann::json history = simulation.With(sgd::ToJson(options, parameters, fit));
  WriteResults(out, history, reports::ConvergencePlot(fit.fit));
  Summarise(parameters, fit.fit, history, summary);
  summary->brief = fit.fit.BriefReport() + ", " + std::to_string(fit.total_simulation_equivalents) +
                   " simulation-equivalents";
}

// The caller's registry entry named by --fit-backend (InputError: unknown name, no file).
backends::Backend FitBackendOf(const FitRequest& r) {
  const backends::Registry registry =
      backends::LoadRegistry(backends::RegistryOptionsFromEnvironment(r.backends_file));
  return registry.Find(r.fit_backend);
}

// A named backend's evaluations read the configuration the history records, written before
// the first one (and removed again when the fit fails, as the other kinds leave none).
sgd::Simulator BackendSimulatorRecorded(const FitRequest& r, const engine::SiberneticConfig& config,
                                        const std::vector<sgd::Parameter>& parameters,
                                        nlohmann::json* record) {
  backends::Backend backend = FitBackendOf(r);
  std::vector<std::string> names;
  for (const sgd::Parameter& p : parameters) names.push_back(p.name);
  sgd::CheckFittableBackend(backend, names);
  sgd::BackendRun run;
  run.configuration = fs::path(r.out) / sgd::kFitConfigurationFile;
  run.duration_s = r.time_s;
  run.time_step_s = engine::PhysicsConstants{}.time_step_s;
  run.log_step = r.log_step;
  *record = sgd::BackendSimulationJson(backend, run, sgd::RecordConfiguration(config, r.out));
  return sgd::BackendSimulator(std::move(backend), run, parameters);
}

void FiniteDifferenceFit(const FitRequest& r, const engine::SiberneticConfig* config,
                         const std::function<bool()>& cancelled, FitDirectorySummary* summary) {
  if (r.targets.empty()) throw InputError("fit: at least one --target is required");
  const std::vector<sgd::Parameter> parameters = ParametersOf(r);
  std::vector<sgd::Target> targets;
  for (const std::string& t : r.targets) targets.push_back(sgd::ParseTarget(t));
  const fs::path out = r.out;
  CreateOutputDirectories(out);
  sgd::Simulator simulator;
  engine::RunOptions run;
  run.duration_s = r.time_s;
  run.log_step = r.log_step;
  run.backend = r.backend.empty() ? "pcisph" : r.backend;
  nlohmann::json backend_record;
  SimulationRecord simulation([&]() -> nlohmann::json {
    if (!r.command.empty()) return {{"kind", "command"}, {"command", r.command}};  // not rerun
    if (!r.fit_backend.empty()) return backend_record;
    return sgd::EngineSimulationJson(run, sgd::RecordConfiguration(*config, out));
  });
  if (!r.command.empty())
    simulator = sgd::CommandSimulator(r.command, parameters, out / "evaluations");
  else if (!r.fit_backend.empty())
    simulator = BackendSimulatorRecorded(r, *config, parameters, &backend_record);
  else
    simulator = sgd::EngineSimulator(*config, run, parameters);
  sgd::FitOptions options;
  options.solver = sgd::ParseSolver(r.solver);
  options.loss_threshold = r.threshold;
  options.max_iterations = r.max_iterations;
  options.learning_rate = r.learning_rate;
  const nlohmann::json targets_json = sgd::TargetsToJson(targets, r.track);
  options.on_iteration = [&](const nlohmann::json& history) {
    nlohmann::json h = history;
    h["targets"] = targets_json;
    WriteProgress(out, simulation.With(h), r.quiet);
  };
  options.cancelled = cancelled;
  sgd::FitSummary fit;
  try {
    sgd::Fit(options, parameters, sgd::MakeObjective(simulator, r.track, targets), &fit);
  } catch (...) {
    std::error_code ec;  // a fit refused before its first history leaves no configuration
    if (!r.fit_backend.empty() && !fs::exists(out / "history.json", ec))
      fs::remove(out / sgd::kFitConfigurationFile, ec);
    throw;
  }
  const nlohmann::json history =
      simulation.With(sgd::ToJson(options, parameters, fit, targets_json));
  WriteResults(out, history, reports::ConvergencePlot(fit));
  Summarise(parameters, fit, history, summary);
  summary->brief = fit.BriefReport();
}

// What this kind of fit would not read of the flags set away from their defaults, or "": a flag
// accepted and ignored reads as applied (`fit --loss-scale 2` of a finite-difference fit fitted
// exactly as without it).
std::string IgnoredFlag(const FitRequest& r) {
  const FitRequest defaults;
  const bool adam = r.solver == "adam";
  if (r.gradient == "fd") {
    const char* analytic = " (a --gradient analytic or model-fd flag)";
    if (!r.loss_groups.empty()) return std::string("--loss-group") + analytic;
    if (r.loss_scale != defaults.loss_scale) return std::string("--loss-scale") + analytic;
    if (r.window != defaults.window) return std::string("--window") + analytic;
    if (r.clip_norm != defaults.clip_norm) return std::string("--clip-norm") + analytic;
    if (r.checkpoint_every != defaults.checkpoint_every)
      return std::string("--checkpoint-every") + analytic;
    if (!r.reference_file.empty()) return std::string("--reference") + analytic;
    if (r.patience != defaults.patience) return "--patience (--solver adam's, a gradient fit's)";
    if (r.solver != "gd" && r.learning_rate != defaults.learning_rate)
      return "--learning-rate (--solver gd's or adam's)";
    return "";
  }
  if (!r.targets.empty())
    return "--target (a finite-difference fit's; this one's loss is --reference's)";
  if (r.gradient == "model-fd") {  // central differences of the model: no reverse pass
    const char* reverse = " (the reverse pass's: --gradient analytic)";
    if (r.window != defaults.window) return std::string("--window") + reverse;
    if (r.clip_norm != defaults.clip_norm) return std::string("--clip-norm") + reverse;
    if (r.checkpoint_every != defaults.checkpoint_every)
      return std::string("--checkpoint-every") + reverse;
  }
  if (!adam && r.patience != defaults.patience) return "--patience (--solver adam's)";
  if (!adam && r.learning_rate != defaults.learning_rate)
    return "--learning-rate (--solver adam's)";
  return "";
}

// InputError for a request naming two simulators, or a flag the chosen one would not read
// (before anything is written).
void CheckEveryFlagApplies(const FitRequest& r) {
  if (!r.fit_backend.empty() && !r.command.empty())
    throw InputError("fit: --fit-backend and --command are two simulators; give one");
  if (r.gradient != "fd" && !r.fit_backend.empty())
    throw InputError("fit --gradient " + r.gradient + ": takes no --fit-backend");
  if (r.gradient != "fd" && !r.command.empty())
    throw InputError("fit --gradient " + r.gradient + ": takes no --command");
  if (!r.backend.empty()) {
    const std::string runs = !r.command.empty()       ? "--command's program"
                             : !r.fit_backend.empty() ? "backend " + r.fit_backend
                             : r.gradient != "fd"     ? "the XPBD model"
                                                      : "";
    if (!runs.empty())
      throw InputError("fit --backend " + r.backend + ": this fit runs " + runs +
                       ", not an engine scheme; drop --backend");
  }
  if (const std::string flag = IgnoredFlag(r); !flag.empty())
    throw InputError("fit --gradient " + r.gradient + ": " + flag + " does not apply");
}

// The four files a fit writes into --out are none of its inputs: `fit DIR/configuration.txt -o
// DIR` replaced the configuration it fitted with the copy it writes beside the history.
void CheckOutputsAreNotInputs(const FitRequest& r, const engine::SiberneticConfig* config) {
  std::vector<fs::path> inputs = {r.reference_file, r.backends_file};
  if (config) inputs.push_back(config->source);  // "scenario NAME" exists as no file
  for (const std::string& t : r.targets) inputs.push_back(sgd::ParseTarget(t).reference_file);
  for (const char* name :
       {"history.json", "parameters.json", "convergence.svg", "configuration.txt"})
    CheckOutputIsNotAnInput(fs::path(r.out) / name, inputs);
}

}  // namespace

void FitIntoDirectory(const FitRequest& request, const engine::SiberneticConfig* config,
                      FrameSource* reference, const std::function<bool()>& cancelled,
                      FitDirectorySummary* summary) {
  CheckOutputDirectory(request.out);  // before any simulation: "/proc/x", a file, no permission
  MissingDirectories created(request.out);  // a failed fit leaves no empty folder it made
  CheckEveryFlagApplies(request);
  CheckOutputsAreNotInputs(request, config);
  if (request.gradient == "fd") {
    FiniteDifferenceFit(request, config, cancelled, summary);
  } else {
    if (!reference)
      throw InputError("fit --gradient " + request.gradient +
                       ": --reference FILE (a trajectory) is required");
    GradientFit(request, *config, *reference, cancelled, summary);
  }
  created.Keep();
}

void FitNamedIntoDirectory(const FitRequest& request, const std::string& config_name,
                           const fs::path& data_dir, const std::function<bool()>& cancelled,
                           FitDirectorySummary* summary) {
  const bool fd = request.gradient == "fd";
  const engine::SiberneticConfig config = !fd || request.command.empty()
                                              ? scenarios::ResolveConfig(config_name, data_dir)
                                              : engine::SiberneticConfig{};
  // Read frame by frame by the fit, up to the fitted time (an fd fit reads none).
  const std::unique_ptr<FrameSource> reference =
      fd || request.reference_file.empty()
          ? nullptr
          : OpenFrameSource(request.reference_file, {TextLayout::kAuto, request.quiet});
  FitIntoDirectory(request, &config, reference.get(), cancelled, summary);
}

std::string FitDirectorySummary::ToText() const {
  std::string text = brief + "\n";
  for (const auto& [name, value] : values)
    text += "  " + name + " = " + FormatNumber(value, 6) + "\n";
  return text;
}

}  // namespace owval::pipeline
