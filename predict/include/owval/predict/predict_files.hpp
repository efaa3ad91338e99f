#pragma once
// `owval predict` and `owval reconcile` as library calls: a scenario or configuration named as a
// user names it, constants and generator parameters as NAME=VALUE, tolerances as VALUE or
// QUANTITY=VALUE, the JSON written atomically when asked.
#include <filesystem>
#include <string>
#include <vector>

#include "owval/predict/predict.hpp"
#include "owval/trajectory/formats.hpp"

namespace owval::predict {

struct PredictRequest {
  std::string config;               // scenario name or configuration file
  std::vector<std::string> params;  // generator parameters, NAME=NUMBER
  // Constants, NAME=VALUE: Sibernetic ignores [physical parameters], so a constant is changed
  // explicitly, and the prediction then notes that it is no longer about Sibernetic's defaults.
  std::vector<std::string> constants;
  bool omit_quarter_factor = false;
  std::string out;  // prediction.json ("": not written)
  std::filesystem::path data_dir;
};
Prediction PredictNamed(const PredictRequest& request);

struct ReconcileRequest {
  std::string prediction, trajectory;  // prediction.json, the measured trajectory
  // "0.01" (every gated quantity) or "NAME=0.01"; checked before the trajectory is opened.
  std::vector<std::string> tolerances;
  std::string out;  // reconcile.json ("": not written)
  TextReadOptions reading;
};
Reconciliation ReconcileFiles(const ReconcileRequest& request);

}  // namespace owval::predict
