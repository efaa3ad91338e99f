// owval predict / owval reconcile: phase 1 and phase 3.
#include <iostream>

#include "command.hpp"
#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/json_file.hpp"
#include "owval/engine/constants.hpp"
#include "owval/predict/predict.hpp"
#include "owval/scenarios/scenario.hpp"
#include "owval/trajectory/formats.hpp"
#include "resolve.hpp"

namespace owval::cli {
namespace {

struct PredictArgs {
  std::string config, out, prediction, trajectory;
  std::vector<std::string> tolerances, params, constants;
  bool json = false, no_quarter = false;
};

void RunPredict(const PredictArgs& a) {
  predict::PredictOptions options;
  options.omit_quarter_factor = a.no_quarter;
  const scenarios::ResolvedScenario s = scenarios::ResolveScenario(a.config, a.params, DataDir());
  options.scenario = s.name;
  options.predictor = s.predictor;
  // Sibernetic ignores [physical parameters]; --set changes a constant explicitly, and the
  // prediction then notes that it is no longer about Sibernetic's defaults.
  engine::PhysicsConstants constants;
  for (const std::string& c : a.constants) engine::SetConstantAssignment(&constants, c);
  const predict::Prediction p = predict::Predict(s.config, constants, options);
  if (!a.out.empty()) WriteFileAtomically(a.out, p.ToJson().dump(2) + "\n");
  std::cout << (a.json ? p.ToJson().dump(2) + "\n" : predict::PredictionMarkdown(p));
}

// "--tolerance 0.01" (every gated quantity) or "--tolerance NAME=0.01".
void RunReconcile(const PredictArgs& a) {
  const predict::Prediction p =
      predict::Prediction::FromJson(ReadJsonFile(a.prediction), a.prediction);
  predict::ReconcileOptions options;
  for (const std::string& t : a.tolerances) options.AddTolerance(t);
  predict::CheckTolerances(p, options);                      // before the trajectory is opened
  const auto frames = OpenTrajectoryArgument(a.trajectory);  // frame by frame
  const predict::Reconciliation r = predict::Reconcile(p, *frames, options);
  if (!a.out.empty()) WriteFileAtomically(a.out, r.ToJson().dump(2) + "\n");
  std::cout << (a.json ? r.ToJson().dump(2) + "\n" : predict::ReconcileMarkdown(r));
  if (!r.pass) SetExitCode(kExitGateFailed);
}

void SetUp(CLI::App& app) {
  auto a = std::make_shared<PredictArgs>();
  CLI::App* predict =
      app.add_subcommand("predict", "Phase 1: analytic prediction from the configuration alone");
  predict->add_option("config", a->config, "Scenario name (owval scenario list) or configuration")
      ->required();
  predict->add_option("-o,--out", a->out, "Also write the prediction JSON here");
  predict->add_flag("--json", a->json, "Print JSON instead of Markdown");
  predict->add_option("--param", a->params, "Override a scenario generator parameter, NAME=NUMBER");
  predict->add_option("--set", a->constants,
                      "Override a constant, NAME=VALUE (e.g. elasticity_coefficient=5.55e8)");
  predict->add_flag("--no-quarter-factor", a->no_quarter,
                    "Omit Sibernetic's 0.25 spring factor (teaching, tests)");
  predict->callback([a] { RunPredict(*a); });
  CLI::App* reconcile =
      app.add_subcommand("reconcile", "Phase 3: predicted vs measured, with likely causes");
  reconcile->add_option("prediction", a->prediction, "prediction.json from owval predict")
      ->required();
  reconcile->add_option("trajectory", a->trajectory, "Measured trajectory")->required();
  reconcile->add_option("--tolerance", a->tolerances,
                        "Gate tolerance for every gated quantity (VALUE) or one (QUANTITY=VALUE); "
                        "relative for periods and amplitudes, cu for positions");
  reconcile->add_option("-o,--out", a->out, "Also write the reconciliation JSON here");
  reconcile->add_flag("--json", a->json, "Print JSON instead of Markdown");
  reconcile->callback([a] { RunReconcile(*a); });
}

const bool registered = RegisterCommand(&SetUp);

}  // namespace
}  // namespace owval::cli
