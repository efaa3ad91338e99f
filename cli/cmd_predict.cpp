// owval predict / owval reconcile: phase 1 and phase 3 (predict/predict_files.hpp).
#include "command.hpp"
#include "owval/predict/predict_files.hpp"

namespace owval::cli {
namespace {

struct PredictArgs {
  predict::PredictRequest predict;
  predict::ReconcileRequest reconcile;
  bool json = false;
};

void SetUp(CLI::App& app) {
  auto a = std::make_shared<PredictArgs>();
  predict::PredictRequest& p = a->predict;
  p.data_dir = DataDir();
  CLI::App* predict =
      app.add_subcommand("predict", "Phase 1: analytic prediction from the configuration alone");
  predict->add_option("config", p.config, "Scenario name (owval scenario list) or configuration")
      ->check(GivenName())
      ->required();
  predict->add_option("-o,--out", p.out, "Also write the prediction JSON here")
      ->check(OutputPath());
  predict->add_flag("--json", a->json, "Print JSON instead of Markdown");
  predict->add_option("--param", p.params, "Override a scenario generator parameter, NAME=NUMBER");
  predict->add_option("--set", p.constants,
                      "Override a constant, NAME=VALUE (e.g. elasticity_coefficient=5.55e8)");
  predict->add_flag("--no-quarter-factor", p.omit_quarter_factor,
                    "Omit Sibernetic's 0.25 spring factor (teaching, tests)");
  predict->callback([a] {
    const predict::Prediction p = predict::PredictNamed(a->predict);
    std::cout << (a->json ? p.ToJson().dump(2) + "\n" : predict::PredictionMarkdown(p));
  });
  predict::ReconcileRequest& r = a->reconcile;
  CLI::App* reconcile =
      app.add_subcommand("reconcile", "Phase 3: predicted vs measured, with likely causes");
  reconcile->add_option("prediction", r.prediction, "prediction.json from owval predict")
      ->check(GivenName())
      ->required();
  reconcile->add_option("trajectory", r.trajectory, "Measured trajectory")
      ->check(GivenName())
      ->required();
  reconcile->add_option("--tolerance", r.tolerances,
                        "Gate tolerance for every gated quantity (VALUE) or one (QUANTITY=VALUE); "
                        "relative for periods and amplitudes, cu for positions");
  reconcile->add_option("-o,--out", r.out, "Also write the reconciliation JSON here")
      ->check(OutputPath());
  reconcile->add_flag("--json", a->json, "Print JSON instead of Markdown");
  reconcile->callback([a] {
    a->reconcile.reading.quiet = QuietMode();
    const predict::Reconciliation r = predict::ReconcileFiles(a->reconcile);
    std::cout << (a->json ? r.ToJson().dump(2) + "\n" : predict::ReconcileMarkdown(r));
    if (!r.pass) SetExitCode(kExitGateFailed);
  });
}

const bool registered = RegisterCommand(&SetUp);

}  // namespace
}  // namespace owval::cli
