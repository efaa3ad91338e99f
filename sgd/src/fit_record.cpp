#include "owval/sgd/fit_record.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>

#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/format.hpp"
#include "owval/base/input_file.hpp"
#include "owval/engine/constants.hpp"
#include "owval/engine/gradient.hpp"
#include "owval/engine/muscles.hpp"
#include "owval/engine/run.hpp"
#include "owval/sgd/backend_simulator.hpp"
#include "owval/sgd/engine_simulator.hpp"
#include "owval/sgd/gradient_fit.hpp"
#include "owval/sgd/targets.hpp"
#include "owval/trajectory/frame_source.hpp"

namespace owval::sgd {
namespace fs = std::filesystem;
namespace {

constexpr std::uint64_t kFnvOffset = 1469598103934665603ull, kFnvPrime = 1099511628211ull;

std::uint64_t Mix(std::uint64_t h, std::string_view bytes) {
  for (unsigned char c : bytes) h = (h ^ c) * kFnvPrime;
  return h;
}

std::string Hex(std::uint64_t h) {
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
  return hex;
}

// A history that cannot be rerun: the reason, caught by RerunBestIterate.
struct NotVerified {
  std::string why;
};

const nlohmann::json& Member(const nlohmann::json& j, const char* key, const std::string& where) {
  if (!j.is_object() || !j.contains(key)) throw NotVerified{where + " has no \"" + key + "\""};
  return j[key];
}

double NumberMember(const nlohmann::json& j, const char* key, const std::string& where) {
  const nlohmann::json& v = Member(j, key, where);
  if (!v.is_number()) throw NotVerified{where + "." + key + " is not a number"};
  return v.get<double>();
}

std::string StringMember(const nlohmann::json& j, const char* key, const std::string& where) {
  const nlohmann::json& v = Member(j, key, where);
  if (!v.is_string()) throw NotVerified{where + "." + key + " is not a string"};
  return v.get<std::string>();
}

// The recorded configuration, read back and held to its hash; its source name restored (the
// engine's muscle rule reads it).
engine::SiberneticConfig RecordedConfiguration(const nlohmann::json& simulation,
                                               const fs::path& fit_dir) {
  const nlohmann::json& c = Member(simulation, "configuration", "simulation");
  const std::string name = StringMember(c, "file", "simulation.configuration");
  if (name.empty() || fs::path(name).filename().string() != name)
    throw NotVerified{"simulation.configuration.file must name a file beside history.json"};
  const fs::path file = fit_dir / name;
  if (!fs::is_regular_file(file))
    throw NotVerified{"the fit's configuration " + name + " is missing"};
  const std::string text = ReadWholeFile(file);
  const std::string recorded = StringMember(c, "fnv1a64", "simulation.configuration");
  if (Fnv1a64Hex(text) != recorded)
    throw NotVerified{name + " is not the configuration the fit recorded (FNV-1a 64 " +
                      Fnv1a64Hex(text) + ", history says " + recorded + ")"};
  engine::SiberneticConfig config = engine::ParseSiberneticConfig(text, file.string());
  if (c.contains("source") && c["source"].is_string()) config.source = c["source"];
  return config;
}

// The engine reads the names; a history's name it refuses is the history's claim, not verified.
engine::Integrator IntegratorNamed(const std::string& name) {
  try {
    return engine::ParseIntegrator(name);
  } catch (const InputError&) {
    throw NotVerified{"simulation.integrator '" + name + "' is not euler or leapfrog"};
  }
}

engine::MuscleSignal MusclesNamed(const std::string& name) {
  try {
    return engine::ParseMuscleSignal(name);
  } catch (const InputError&) {
    throw NotVerified{"simulation.muscles '" + name + "' is not auto, off or waves"};
  }
}

// The recorded run options (constants included) of an engine fit.
engine::RunOptions RecordedRunOptions(const nlohmann::json& s) {
  engine::RunOptions o;
  o.backend = StringMember(s, "backend", "simulation");
  o.duration_s = NumberMember(s, "duration_s", "simulation");
  const double log_step = NumberMember(s, "log_step", "simulation");
  if (!(log_step >= 1 && log_step == std::floor(log_step) && log_step < 1e9))
    throw NotVerified{"simulation.log_step is not a whole number of steps"};
  o.log_step = int(log_step);
  o.integrator = IntegratorNamed(StringMember(s, "integrator", "simulation"));
  o.muscle_signal = MusclesNamed(StringMember(s, "muscles", "simulation"));
  const nlohmann::json& apply = Member(s, "apply_physical_parameters", "simulation");
  if (!apply.is_boolean())
    throw NotVerified{"simulation.apply_physical_parameters is not a boolean"};
  o.apply_physical_parameters = apply.get<bool>();
  const nlohmann::json& constants = Member(s, "constants", "simulation");
  if (!constants.is_object()) throw NotVerified{"simulation.constants is not an object"};
  for (const auto& [name, value] : constants.items()) {
    if (!value.is_number()) throw NotVerified{"simulation.constants." + name + " is not a number"};
    engine::SetConstant(&o.constants, name, value.get<double>());  // InputError: unknown name
  }
  return o;
}

// The best iteration (final.loss's), whose parameters final.parameters must be.
const nlohmann::json& BestIteration(const nlohmann::json& history) {
  const nlohmann::json& iterations = Member(history, "iterations", "the history");
  if (!iterations.is_array() || iterations.empty())
    throw NotVerified{"the history has no iteration"};
  const nlohmann::json* best = nullptr;
  for (const nlohmann::json& it : iterations) {
    const double loss = NumberMember(it, "loss", "an iteration");
    if (!best || loss < (*best)["loss"].get<double>()) best = &it;
  }
  const nlohmann::json& final_parameters =
      Member(Member(history, "final", "the history"), "parameters", "final");
  if (Member(*best, "parameters", "the best iteration") != final_parameters)
    throw NotVerified{"final.parameters are not the best iteration's parameters"};
  return *best;
}

// The fitted parameters (history "parameters") and their values at the best iterate.
std::vector<Parameter> FittedParameters(const nlohmann::json& history, const nlohmann::json& best,
                                        std::vector<double>* values) {
  std::vector<Parameter> parameters;
  for (const nlohmann::json& p : Member(history, "parameters", "the history")) {
    Parameter parameter;
    parameter.name = StringMember(p, "name", "a parameter");
    parameter.start = NumberMember(p, "start", "a parameter");
    // Optional, a boolean when given: value() threw nlohmann's "type must be boolean".
    if (p.contains("log_space") && !p["log_space"].is_boolean())
      throw NotVerified{"a parameter's log_space is not a boolean"};
    parameter.log_space = p.value("log_space", false);
    parameters.push_back(parameter);
    values->push_back(NumberMember(best["parameters"], parameter.name.c_str(), "best parameters"));
  }
  if (parameters.empty()) throw NotVerified{"the history lists no fitted parameter"};
  if (best["parameters"].size() != parameters.size())
    throw NotVerified{"the best iteration's parameters are not the fitted ones"};
  return parameters;
}

// The targets and their track, the rms ones measured against the caller's reference series.
std::vector<Target> RecordedTargets(const nlohmann::json& history, const FitRerunOptions& options,
                                    Track* track) {
  std::vector<Target> targets;
  const nlohmann::json& list = Member(history, "targets", "the history");
  if (!list.is_array() || list.empty()) throw NotVerified{"the history lists no target"};
  for (const nlohmann::json& t : list) {
    Target target;
    target.metric = StringMember(t, "metric", "a target");
    target.value = NumberMember(t, "value", "a target");
    target.scale = NumberMember(t, "scale", "a target");
    target.weight = NumberMember(t, "weight", "a target");
    const Track tracked = Track::FromJson(Member(t, "track", "a target"), "history.json targets");
    if (!targets.empty() && !(tracked.ToJson() == track->ToJson()))
      throw NotVerified{"the targets track different quantities"};
    *track = tracked;
    if (target.metric == "rms") {
      if (!options.rms_reference)
        throw NotVerified{"an rms target needs the directory's reference trajectory"};
      target.reference = options.rms_reference;
      target.reference_file = "the directory's reference";
    }
    targets.push_back(target);
  }
  return targets;
}

// The best iterate of a fit scored by targets (the engine's, a named backend's): its parameters'
// names and values, and the targets with their track.
struct ScoredIterate {
  nlohmann::json best;
  std::vector<std::string> names;
  std::vector<double> values;
  Track track;
  std::vector<Target> targets;
};

ScoredIterate BestScoredIterate(const nlohmann::json& history, const FitRerunOptions& options) {
  ScoredIterate b;
  b.best = BestIteration(history);
  for (const Parameter& p : FittedParameters(history, b.best, &b.values)) b.names.push_back(p.name);
  b.targets = RecordedTargets(history, options, &b.track);
  return b;
}

// The rerun of `b` scored: its residuals against the targets and their sum of squares.
FitRerun Scored(const ScoredIterate& b, const TrackedSeries& series, std::string simulated) {
  FitRerun r;
  r.best_iteration = b.best;
  r.residuals = ScaledResiduals(series, b.track, b.targets);
  for (double v : r.residuals) r.loss += v * v;
  r.simulated = std::move(simulated);
  return r;
}

FitRerun RerunEngineFit(const nlohmann::json& history, const nlohmann::json& simulation,
                        const fs::path& fit_dir, const FitRerunOptions& options) {
  const engine::SiberneticConfig config = RecordedConfiguration(simulation, fit_dir);
  engine::RunOptions base = RecordedRunOptions(simulation);
  const ScoredIterate b = BestScoredIterate(history, options);
  engine::RunOptions run = EvaluationRunOptions(base, b.names, b.values);
  run.on_step = options.on_step;  // the fit's evaluations run concurrently, without one
  return Scored(b, RunTrackedSeries(config, run, b.track),
                run.backend + ", " + FormatNumber(run.duration_s) + " s, log step " +
                    std::to_string(run.log_step) + ", " +
                    simulation["configuration"]["file"].get<std::string>());
}

// A fit of a named backend, rerun through the caller's entry (options.backend) with the recorded
// configuration (held to its hash), time span, time step and log step.
FitRerun RerunBackendFit(const nlohmann::json& history, const nlohmann::json& simulation,
                         const fs::path& fit_dir, const FitRerunOptions& options) {
  // Optional (the report names it), but a string when given: value() threw nlohmann's "type must
  // be string, but is number", which reached the checklist's report as it was.
  const std::string fitted =
      simulation.contains("name") ? StringMember(simulation, "name", "simulation") : "?";
  if (!options.backend)
    throw NotVerified{"a fit of backend '" + fitted +
                      "' is rerun only through the reviewer's own registry entry "
                      "(--fit-backend NAME), never the command the history records"};
  RecordedConfiguration(simulation, fit_dir);  // the file, held to its hash
  BackendRun run;
  run.configuration =
      fit_dir / StringMember(simulation["configuration"], "file", "simulation.configuration");
  run.duration_s = NumberMember(simulation, "duration_s", "simulation");
  if (!(run.duration_s > 0)) throw NotVerified{"simulation.duration_s is not positive"};
  run.time_step_s = NumberMember(simulation, "time_step_s", "simulation");
  if (run.time_step_s != engine::PhysicsConstants{}.time_step_s)
    throw NotVerified{"simulation.time_step_s " + FormatNumber(run.time_step_s, 6) +
                      " is not Sibernetic's " +
                      FormatNumber(engine::PhysicsConstants{}.time_step_s, 6) + " s"};
  const double log_step = NumberMember(simulation, "log_step", "simulation");
  if (!(log_step >= 1 && log_step == std::floor(log_step) && log_step < 1e9))
    throw NotVerified{"simulation.log_step is not a whole number of steps"};
  run.log_step = int(log_step);
  const ScoredIterate b = BestScoredIterate(history, options);
  CheckFittableBackend(*options.backend, b.names);  // InputError: not verified, with the reason
  // The reviewer's registry may name the port otherwise; a different name may also be a rerun
  // through another substrate than the one fitted. Not a failure (the rerun's loss is judged
  // either way), but the report says so.
  const std::string renamed =
      fitted == options.backend->name ? "" : " (the history fitted backend '" + fitted + "')";
  return Scored(b, RunBackendTrackedSeries(*options.backend, run, b.names, b.values, b.track),
                "backend " + options.backend->name + " of the caller's " +
                    options.backend->defined_in + renamed + ", " + FormatNumber(run.duration_s) +
                    " s, log step " + std::to_string(run.log_step) + ", " +
                    run.configuration.filename().string());
}

FitRerun RerunModelFit(const nlohmann::json& history, const nlohmann::json& simulation,
                       const fs::path& fit_dir, const FitRerunOptions& options) {
  const engine::SiberneticConfig config = RecordedConfiguration(simulation, fit_dir);
  const double steps = NumberMember(simulation, "steps", "simulation");
  if (!(steps >= 1 && steps == std::floor(steps) && steps < 1e12))
    throw NotVerified{"simulation.steps is not a whole number of steps"};
  const nlohmann::json& loss = Member(simulation, "loss", "simulation");
  if (!options.loss_reference)
    throw NotVerified{"a gradient fit's loss needs the directory's reference trajectory"};
  const Track track = Track::FromJson(Member(loss, "track", "simulation.loss"), "history.json");
  std::vector<std::string> groups;
  for (const nlohmann::json& g : Member(loss, "groups", "simulation.loss")) {
    if (!g.is_string()) throw NotVerified{"simulation.loss.groups holds a non-string"};
    groups.push_back(g.get<std::string>());
  }
  const double scale = NumberMember(loss, "scale", "simulation.loss");
  FrameSource& frames = *options.loss_reference;
  const std::vector<engine::LossTerm> terms =
      groups.empty() ? TrackLoss(frames, track, std::size_t(steps), scale)
                     : GroupCentroidLoss(frames, groups, std::size_t(steps), scale);
  std::vector<double> values;
  const nlohmann::json& best = BestIteration(history);
  const std::vector<Parameter> parameters = FittedParameters(history, best, &values);
  const engine::DifferentiableXpbd model(config, engine::PhysicsConstants{});
  FitRerun r;
  r.best_iteration = best;
  r.residuals = GradientFitResiduals(model, parameters, values, terms, std::size_t(steps));
  for (double v : r.residuals) r.loss += v * v;
  r.simulated = "the XPBD model, " + std::to_string(std::size_t(steps)) + " steps, " +
                simulation["configuration"]["file"].get<std::string>() +
                ", loss against the directory's reference";
  return r;
}

}  // namespace

std::string Fnv1a64Hex(std::string_view bytes) { return Hex(Mix(kFnvOffset, bytes)); }

std::string FileFnv1a64Hex(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string(), 0, "cannot be read");
  std::uint64_t h = kFnvOffset;
  std::string block(1 << 20, '\0');
  while (in) {
    in.read(block.data(), std::streamsize(block.size()));
    h = Mix(h, std::string_view(block.data(), std::size_t(in.gcount())));
  }
  return Hex(h);
}

nlohmann::json RecordConfiguration(const engine::SiberneticConfig& config,
                                   const fs::path& fit_dir) {
  const fs::path file = fit_dir / kFitConfigurationFile;
  engine::WriteSiberneticConfig(config, file);
  return {{"file", kFitConfigurationFile},
          {"fnv1a64", Fnv1a64Hex(ReadWholeFile(file))},
          {"source", config.source}};
}

nlohmann::json EngineSimulationJson(const engine::RunOptions& run,
                                    const nlohmann::json& configuration) {
  nlohmann::json constants = nlohmann::json::object();
  const engine::PhysicsConstants defaults;
  for (const engine::ConstantInfo& c : engine::PhysicsConstantTable())
    if (c.get(run.constants) != c.get(defaults)) constants[c.name] = c.get(run.constants);
  return {{"kind", "engine"},
          {"backend", run.backend},
          {"configuration", configuration},
          {"duration_s", run.duration_s},
          {"log_step", run.log_step},
          {"integrator", engine::IntegratorName(run.integrator)},
          {"muscles", engine::MuscleSignalName(run.muscle_signal)},
          {"apply_physical_parameters", run.apply_physical_parameters},
          {"constants", constants}};
}

nlohmann::json ModelSimulationJson(const nlohmann::json& configuration, std::size_t steps,
                                   const fs::path& reference_file, const Track& track,
                                   const std::vector<std::string>& groups, double scale_cu) {
  return {{"kind", "xpbd_model"},
          {"configuration", configuration},
          {"steps", steps},
          {"loss",
           {{"reference",
             {{"file", fs::absolute(reference_file).lexically_normal().string()},
              {"fnv1a64", FileFnv1a64Hex(reference_file)}}},
            {"track", track.ToJson()},
            {"groups", groups},
            {"scale", scale_cu}}}};
}

engine::RunOptions EvaluationRunOptions(engine::RunOptions base,
                                        const std::vector<std::string>& parameter_names,
                                        const std::vector<double>& values) {
  base.record_fields = false;  // fits read positions only
  base.threads = 1;            // finite-difference points already run concurrently
  base.on_step = nullptr;
  for (std::size_t i = 0; i < parameter_names.size(); ++i)
    engine::SetConstant(&base.constants, parameter_names[i], values[i]);
  return base;
}

FitRerun RerunBestIterate(const nlohmann::json& history, const fs::path& fit_dir,
                          const FitRerunOptions& options) {
  try {
    if (!history.is_object() || !history.contains("simulation"))
      throw NotVerified{"the history records no \"simulation\" to rerun (schema " +
                        std::string(kFitHistorySchema) + " does)"};
    const nlohmann::json& simulation = history["simulation"];
    const std::string kind = StringMember(simulation, "kind", "simulation");
    if (kind == "engine") return RerunEngineFit(history, simulation, fit_dir, options);
    if (kind == "xpbd_model") return RerunModelFit(history, simulation, fit_dir, options);
    if (kind == "backend") return RerunBackendFit(history, simulation, fit_dir, options);
    throw NotVerified{"simulation.kind '" + kind +
                      "' cannot be rerun by owval (an external --command fit records a template of "
                      "the pull request's choosing; fit a named backend, --fit-backend NAME, "
                      "to have it rerun through the reviewer's own entry)"};
  } catch (const NotVerified& e) {
    return {e.why, {}, 0, "", {}};
  } catch (const std::exception& e) {  // InputError, SimulationError: the record does not run
    return {std::string("the recorded simulation does not run: ") + e.what(), {}, 0, "", {}};
  }
}

}  // namespace owval::sgd
