// owval predict / owval reconcile: phase 1 and phase 3 (predict/predict_files.hpp).
#include "command.hpp"
#include "owval/predict/predict_files.hpp"
#include "run_flags.hpp"

namespace owval::cli {
namespace {

struct PredictArgs {
  predict::PredictRequest predict;
  predict::ReconcileRequest reconcile;
  bool json = false;
};

void SetUpPredict(CLI::App& app) {
  auto a = std::make_shared<PredictArgs>();
  predict::PredictRequest& p = a->predict;
  p.data_dir = DataDir();
  CLI::App* predict =
      app.add_subcommand("predict", "Phase 1: analytic prediction from the configuration alone");
  AddInput(predict, "config", &p.config, "Scenario name (owval scenario list) or configuration");
  AddOut(predict, &p.out, "Also write the prediction JSON here");
  AddJsonFlag(predict, &a->json, "the prediction");
  AddGeneratorParams(predict, &p.params);
  AddConstantOverrides(predict, &p.constants);
  predict->add_flag("--no-quarter-factor", p.omit_quarter_factor,
                    "Omit Sibernetic's 0.25 spring factor (teaching, tests)");
  predict->callback([a] {
    const predict::Prediction p = predict::PredictNamed(a->predict);
    std::cout << (a->json ? p.ToJson().dump(2) + "\n" : predict::PredictionMarkdown(p));
  });
  predict::ReconcileRequest& r = a->reconcile;
  CLI::App* reconcile =
      app.add_subcommand("reconcile", "Phase 3: predicted vs measured, with likely causes");
  AddInput(reconcile, "prediction", &r.prediction, "prediction.json from owval predict");
  AddInput(reconcile, "trajectory", &r.trajectory, "Measured trajectory");
  reconcile->add_option("--tolerance", r.tolerances,
                        "Gate tolerance for every gated quantity (VALUE) or one (QUANTITY=VALUE); "
                        "relative for periods and amplitudes, cu for positions");
  AddOut(reconcile, &r.out, "Also write the reconciliation JSON here");
  AddJsonFlag(reconcile, &a->json, "the reconciliation");
  reconcile->callback([a] {
    a->reconcile.reading.quiet = QuietMode();
    const predict::Reconciliation r = predict::ReconcileFiles(a->reconcile);
    std::cout << (a->json ? r.ToJson().dump(2) + "\n" : predict::ReconcileMarkdown(r));
    if (!r.pass) SetExitCode(kExitGateFailed);
  });
}

const bool predict_registered = RegisterCommand(&SetUpPredict);

}  // namespace
}  // namespace owval::cli
