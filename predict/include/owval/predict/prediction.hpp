#pragma once
// What phase 1 predicts and phase 3 measures, as types: a Prediction (made from a configuration
// alone) and a Reconciliation (the prediction against a trajectory). JSON exists only at the
// edges: ToJson for prediction.json / reconcile.json, FromJson for a prediction.json someone
// hands in (schema: docs/prediction.md), which checks every field and names the file and field.
#include <cstddef>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "owval/trajectory/track.hpp"

namespace owval::predict {

// How a quantity is gated: |measured/predicted - 1| (relative), |measured - predicted| in cu
// (absolute_cu), or not at all (informative: reported, never gated).
enum class ToleranceKind { kRelative, kAbsoluteCu, kInformative };
const char* ToleranceKindName(ToleranceKind kind);  // "relative", "absolute_cu", "informative"

// A number a formula uses, with where it came from (a configuration line or a default constant).
struct PredictionInput {
  std::string name;
  double value = 0;
  std::string unit;
  std::string source;
};

struct PredictedQuantity {
  std::string quantity;  // reconcile measures it by this name (docs/prediction.md's table)
  double value = 0;      // configuration units (cu for positions)
  std::string unit;
  double value_si = 0;
  std::string unit_si;
  std::string formula;
  double tolerance = 0;
  ToleranceKind tolerance_kind = ToleranceKind::kRelative;
  // A table for readers beside the quantity (hanging_chain's per-bead equilibria under "beads",
  // hydrostatic_column's per-layer pressures under "profile"); reconcile never reads it.
  std::string detail_key;
  nlohmann::json detail;
};

struct Prediction {
  std::string predictor;      // harmonic_spring | free_fall | hanging_chain | hydrostatic_column
  std::string scenario;       // scenario name or configuration file name
  std::string configuration;  // where the configuration came from
  bool omit_quarter_factor = false;
  Track track;  // what reconcile measures
  std::vector<PredictionInput> inputs;
  std::vector<PredictedQuantity> predictions;
  std::vector<std::string> notes;  // caveats

  // The quantity of that name, or nullptr.
  const PredictedQuantity* Find(const std::string& quantity) const;
  // Its predicted value, NaN when there is no such quantity.
  double ValueOf(const std::string& quantity) const;
  // The input's value, NaN when there is no such input.
  double InputValue(const std::string& name) const;

  nlohmann::json ToJson() const;  // schema owval.prediction/1
  // Reads owval.prediction/1; InputError naming `file` and the field for anything malformed.
  static Prediction FromJson(const nlohmann::json& json, const std::string& file);
};

struct ReconcileRow {
  std::string quantity;
  double predicted = 0;
  std::string unit;
  double tolerance = 0;  // 0 for informative quantities
  ToleranceKind tolerance_kind = ToleranceKind::kRelative;
  bool gap_in_cu = false;  // gap |measured - predicted| in cu; else relative to the prediction
  std::optional<double> measured, gap;
  std::optional<bool> pass;  // empty for informative quantities
  std::string hint;          // likely cause when it failed, or why it could not be measured
};

struct Reconciliation {
  std::string predictor, scenario;
  std::string signal;  // "particle 0 y", "liquid centroid y"
  std::size_t frames = 0;
  std::vector<ReconcileRow> rows;
  bool pass = true;  // every gated row passed

  const ReconcileRow* Find(const std::string& quantity) const;
  nlohmann::json ToJson() const;  // schema owval.reconcile/1
};

}  // namespace owval::predict
