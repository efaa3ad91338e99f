#include "owval/predict/predict_files.hpp"

#include <filesystem>
#include <string>
#include <vector>

#include "owval/base/atomic_output.hpp"
#include "owval/base/json_file.hpp"
#include "owval/engine/constants.hpp"
#include "owval/scenarios/scenario.hpp"
#include "owval/trajectory/frame_source.hpp"

namespace owval::predict {
namespace {

// -o is checked before any work, and against the inputs: `predict CONFIG -o CONFIG` and
// `reconcile P T -o P` replaced the input with the JSON (exit 0), `-o DIR` failed only at the
// rename, after the work.
void CheckJsonOutput(const std::string& out, const std::vector<std::filesystem::path>& inputs) {
  if (out.empty()) return;
  CheckOutputPath(out);
  CheckOutputIsNotAnInput(out, inputs);
}

}  // namespace

Prediction PredictNamed(const PredictRequest& r) {
  CheckJsonOutput(r.out, {r.config});
  PredictOptions options;
  options.omit_quarter_factor = r.omit_quarter_factor;
  const scenarios::ResolvedScenario s = scenarios::ResolveScenario(r.config, r.params, r.data_dir);
  options.scenario = s.name;
  options.predictor = s.predictor;
  engine::PhysicsConstants constants;
  engine::SetConstantAssignments(&constants, r.constants);
  const Prediction p = Predict(s.config, constants, options);
  if (!r.out.empty()) WriteFileAtomically(r.out, p.ToJson().dump(2) + "\n");
  return p;
}

Reconciliation ReconcileFiles(const ReconcileRequest& r) {
  CheckJsonOutput(r.out, {r.prediction, r.trajectory});
  const Prediction p = Prediction::FromJson(ReadJsonFile(r.prediction), r.prediction);
  ReconcileOptions options;
  for (const std::string& t : r.tolerances) options.AddTolerance(t);
  CheckTolerances(p, options);                                   // before the trajectory is opened
  const auto frames = OpenFrameSource(r.trajectory, r.reading);  // frame by frame
  RequireFrames(*frames, r.trajectory, 2);                       // a measurement over time
  const Reconciliation reconciliation = Reconcile(p, *frames, options);
  if (!r.out.empty()) WriteFileAtomically(r.out, reconciliation.ToJson().dump(2) + "\n");
  return reconciliation;
}

}  // namespace owval::predict
