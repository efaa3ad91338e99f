#include "fit_phase.hpp"

#include <algorithm>
#include <cmath>

#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"
#include "owval/compare/signal_metrics.hpp"
#include "owval/engine/gradient.hpp"
#include "owval/engine/solver.hpp"
#include "owval/sgd/engine_simulator.hpp"
#include "owval/sgd/finite_difference.hpp"
#include "owval/sgd/fit_record.hpp"
#include "owval/sgd/gradcheck.hpp"
#include "owval/sgd/targets.hpp"
#include "trajectory_files.hpp"

namespace owval::pipeline {
namespace fs = std::filesystem;
namespace {

engine::RunOptions RunOptionsFor(const FitPhase& f) {
  engine::RunOptions o;
  o.duration_s = f.scenario.duration_s;
  o.log_step = f.scenario.log_step;
  o.backend = f.backend;
  return o;
}

// `owval gradcheck all` with the end-to-end test on the scenario's configuration.
bool RunGradCheck(const FitPhase& f, std::string* outcome) {
  const fs::path config = f.dir / "configuration.txt";
  engine::WriteSiberneticConfig(f.config, config);
  engine::GradCheckOptions options;
  options.end_to_end_config = config.string();
  const engine::GradCheckSummary summary = engine::RunGradCheck(options);
  WriteFileAtomically(f.dir / "fd_tests.json", sgd::GradCheckJson(summary, options).dump(2) + "\n");
  *outcome = "owval gradcheck all (xpbd): " + summary.BriefReport();
  return true;
}

// A number member of a manifest object, or InputError naming the manifest and the key.
double Number(const nlohmann::json& j, const char* key, const std::string& where) {
  if (!j.is_object() || !j.contains(key) || !j[key].is_number())
    throw InputError(where, 0, std::string("\"fit\": expected a number \"") + key + "\"");
  return j[key].get<double>();
}

std::vector<sgd::Parameter> Parameters(const nlohmann::json& fit, const std::string& where) {
  std::vector<sgd::Parameter> out;
  for (const auto& p : fit.value("parameters", nlohmann::json::array())) {
    if (!p.is_object() || !p.contains("name") || !p["name"].is_string())
      throw InputError(where, 0, "\"fit.parameters\": expected objects with a \"name\"");
    sgd::Parameter parameter{p["name"].get<std::string>(), Number(p, "start", where),
                             p.value("log", false)};
    if (p.contains("lower")) parameter.lower = Number(p, "lower", where);
    if (p.contains("upper")) parameter.upper = Number(p, "upper", where);
    out.push_back(parameter);
  }
  return out;
}

// The targets' values measured on the reference; empty optional with `why` when one cannot be.
std::optional<std::vector<sgd::Target>> Targets(const FitPhase& f, const nlohmann::json& fit,
                                                std::string* why) {
  const TrackedSeries reference = ReadTrackedSeries(f.dir / "reference.h5", f.scenario.track);
  const std::vector<double>& series = reference.value;
  const compare::SignalMetrics m = compare::MeasureSignal(reference.time_s, series);
  const auto [lo, hi] = std::minmax_element(series.begin(), series.end());
  const double range = *hi - *lo > 0 ? *hi - *lo : 1.0;
  std::vector<sgd::Target> targets;
  for (const auto& t : fit.value("targets", nlohmann::json::array())) {
    const std::string metric = t.value("metric", std::string());
    const double weight = t.value("weight", 1.0);
    if (metric == "rms") {  // the reference's tracked series, read above
      targets.push_back({"rms", 0, range, weight, (f.dir / "reference.h5").string(),
                         std::make_shared<const TrackedSeries>(reference)});
      continue;
    }
    const std::optional<double> value = metric == "period"           ? m.period_s
                                        : metric == "half_amplitude" ? m.half_amplitude
                                        : metric == "equilibrium"    ? std::optional(m.equilibrium)
                                                                     : std::nullopt;
    if (!value) {
      *why = "the reference has no " + metric + " of " + f.scenario.track.Describe() + " to fit to";
      return std::nullopt;
    }
    targets.push_back({metric, *value, std::max(std::abs(*value), 1e-12), weight, "", nullptr});
  }
  return targets;
}

}  // namespace

std::string RunFit(const FitPhase& f, std::optional<reports::FitEvidence>* fit) {
  const std::string where = "scenarios/manifests/" + f.scenario.name + ".json";
  if (!f.scenario.manifest.contains("fit"))
    return "the scenario's manifest names no parameter to fit";
  const nlohmann::json& spec = f.scenario.manifest["fit"];
  reports::FitEvidence evidence;
  evidence.parameters = Parameters(spec, where);
  std::string why;
  const auto targets = Targets(f, spec, &why);
  if (evidence.parameters.empty() || !targets || targets->empty())
    return why.empty() ? "the manifest's \"fit\" has no parameters or targets" : why;
  const Track& tracking = f.scenario.track;
  const nlohmann::json targets_json = sgd::TargetsToJson(*targets, tracking);
  const fs::path history = f.dir / "fit" / "history.json";
  CreateOutputDirectories(f.dir / "fit");
  // What the evaluations simulate, with the configuration beside the history: the checklist
  // reruns the best iterate from this record (docs/fit_history.md).
  const nlohmann::json simulation = sgd::EngineSimulationJson(
      RunOptionsFor(f), sgd::RecordConfiguration(f.config, f.dir / "fit"));
  sgd::FitOptions options;
  options.solver = evidence.solver;
  options.on_iteration = [&](const nlohmann::json& h) {
    nlohmann::json recorded = h;
    recorded["targets"] = targets_json;
    recorded["simulation"] = simulation;
    WriteFileAtomically(history, recorded.dump(2) + "\n");
  };
  sgd::Fit(options, evidence.parameters,
           sgd::MakeObjective(sgd::EngineSimulator(f.config, RunOptionsFor(f), evidence.parameters),
                              tracking, *targets),
           &evidence.summary);
  nlohmann::json j = sgd::ToJson(options, evidence.parameters, evidence.summary, targets_json);
  j["simulation"] = simulation;
  WriteFileAtomically(history, j.dump(2) + "\n");
  WriteFileAtomically(f.dir / "fit" / "convergence.svg",
                      reports::ConvergencePlot(evidence.summary));
  WriteFileAtomically(f.dir / "parameters.json",
                      nlohmann::json{{"parameters", j["final"]["parameters"]},
                                     {"loss", evidence.summary.final_loss},
                                     {"simulations", evidence.summary.evaluations}}
                              .dump(2) +
                          "\n");
  const std::string brief = evidence.summary.BriefReport();
  *fit = std::move(evidence);
  return brief;
}

bool RunFiniteDifferenceTest(const FitPhase& f, std::string* outcome) {
  if (engine::CanonicalBackend(f.backend) == "xpbd") return RunGradCheck(f, outcome);
  const std::string kind = f.scenario.manifest.value("fd_test", std::string());
  if (kind.empty()) {
    *outcome = "the scenario's manifest names no kernel to test";
    return false;
  }
  if (kind != "spring_period_vs_log_k")
    throw InputError("scenarios/manifests/" + f.scenario.name + ".json", 0,
                     "\"fd_test\": expected spring_period_vs_log_k");
  const sgd::Simulator simulate =
      sgd::EngineSimulator(f.config, RunOptionsFor(f), {{"elasticity_coefficient", 3e8, true}});
  auto period = [&](double log_k) {
    const TrackedSeries run = simulate({std::exp(log_k)}, f.scenario.track);
    const auto m = compare::MeasureSignal(run.time_s, run.value);
    if (!m.period_s)
      throw InputError("finite-difference test: no oscillation at k = " +
                       std::to_string(std::exp(log_k)));
    return *m.period_s;
  };
  const double log_k = std::log(engine::PhysicsConstants{}.elasticity_coefficient);
  sgd::FiniteDifferenceTest test{"elastic kernel: d(period)/d(log k) = -period/2", log_k, 0.1,
                                 -period(log_k) / 2, 0.02};
  sgd::RunFiniteDifferenceTest(period, &test);
  WriteFileAtomically(f.dir / "fd_tests.json",
                      sgd::FiniteDifferenceTestsJson({test}).dump(2) + "\n");
  *outcome = test.name + ": " + (test.pass ? "pass" : "FAIL");
  return true;
}

}  // namespace owval::pipeline
