// owval predict / owval reconcile: phase 1 and phase 3.
#include <iostream>

#include "command.hpp"
#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"
#include "owval/predict/predict.hpp"
#include "owval/trajectory/formats.hpp"
#include "resolve.hpp"

namespace owval::cli {
namespace {

struct PredictArgs {
  std::string config, out, prediction, trajectory;
  bool json = false, no_quarter = false;
};

void RunPredict(const PredictArgs& a) {
  predict::PredictOptions options;
  options.scenario = a.config;
  options.omit_quarter_factor = a.no_quarter;
  const nlohmann::json p =
      predict::Predict(ResolveConfig(a.config), engine::PhysicsConstants{}, options);
  if (!a.out.empty()) WriteFileAtomically(a.out, p.dump(2) + "\n");
  std::cout << (a.json ? p.dump(2) + "\n" : predict::PredictionMarkdown(p));
}

void RunReconcile(const PredictArgs& a) {
  nlohmann::json p;
  try {
    p = nlohmann::json::parse(ReadWholeFile(a.prediction));
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(a.prediction, 0, std::string("not valid JSON: ") + e.what());
  }
  TextReadOptions read;
  read.quiet = Flags().quiet;
  const nlohmann::json r = predict::Reconcile(p, ReadTrajectory(a.trajectory, read));
  if (!a.out.empty()) WriteFileAtomically(a.out, r.dump(2) + "\n");
  std::cout << (a.json ? r.dump(2) + "\n" : predict::ReconcileMarkdown(r));
  if (!r["pass"].get<bool>()) SetExitCode(kExitGateFailed);
}

void SetUp(CLI::App& app) {
  auto a = std::make_shared<PredictArgs>();
  CLI::App* predict =
      app.add_subcommand("predict", "Phase 1: analytic prediction from the configuration alone");
  predict->add_option("config", a->config, "Scenario name or Sibernetic configuration")->required();
  predict->add_option("-o,--out", a->out, "Also write the prediction JSON here");
  predict->add_flag("--json", a->json, "Print JSON instead of Markdown");
  predict->add_flag("--no-quarter-factor", a->no_quarter,
                    "Omit Sibernetic's 0.25 spring factor (teaching, tests)");
  predict->callback([a] { RunPredict(*a); });
  CLI::App* reconcile =
      app.add_subcommand("reconcile", "Phase 3: predicted vs measured, with likely causes");
  reconcile->add_option("prediction", a->prediction, "prediction.json from owval predict")
      ->required();
  reconcile->add_option("trajectory", a->trajectory, "Measured trajectory")->required();
  reconcile->add_option("-o,--out", a->out, "Also write the reconciliation JSON here");
  reconcile->add_flag("--json", a->json, "Print JSON instead of Markdown");
  reconcile->callback([a] { RunReconcile(*a); });
}

const bool registered = RegisterCommand(&SetUp);

}  // namespace
}  // namespace owval::cli
