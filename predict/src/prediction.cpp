#include "owval/predict/prediction.hpp"

#include <cmath>

#include "owval/base/errors.hpp"

namespace owval::predict {
namespace {

using nlohmann::json;

// Field readers for FromJson: each names the file and the field's path when it is malformed.
class Fields {
 public:
  explicit Fields(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void Fail(const std::string& path, const std::string& expected) const {
    throw InputError(file_, 0, "\"" + path + "\": expected " + expected);
  }
  std::string String(const json& j, const char* key, const std::string& path,
                     bool required = false) const {
    if (!j.contains(key)) {
      if (required) Fail(path, "a string");
      return "";
    }
    if (!j[key].is_string()) Fail(path, "a string");
    return j[key].get<std::string>();
  }
  double Number(const json& j, const char* key, const std::string& path, bool required) const {
    if (!j.contains(key)) {
      if (required) Fail(path, "a finite number");
      return 0;
    }
    if (!j[key].is_number() || !std::isfinite(j[key].get<double>())) Fail(path, "a finite number");
    return j[key].get<double>();
  }
  const json& Array(const json& j, const char* key, const std::string& path) const {
    static const json empty = json::array();
    if (!j.contains(key)) return empty;
    if (!j[key].is_array()) Fail(path, "a list");
    return j[key];
  }
  const std::string& file() const { return file_; }

 private:
  std::string file_;
};

ToleranceKind ParseToleranceKind(const std::string& name, const Fields& f,
                                 const std::string& path) {
  for (ToleranceKind k :
       {ToleranceKind::kRelative, ToleranceKind::kAbsoluteCu, ToleranceKind::kInformative})
    if (name == ToleranceKindName(k)) return k;
  f.Fail(path, "relative, absolute_cu or informative");
}

PredictedQuantity QuantityFromJson(const json& q, const Fields& f, const std::string& path) {
  if (!q.is_object()) f.Fail(path, "an object");
  PredictedQuantity p;
  p.quantity = f.String(q, "quantity", path + ".quantity", true);
  p.value = f.Number(q, "value", path + ".value", true);
  p.unit = f.String(q, "unit", path + ".unit");
  p.value_si = f.Number(q, "value_si", path + ".value_si", false);
  p.unit_si = f.String(q, "unit_si", path + ".unit_si");
  p.formula = f.String(q, "formula", path + ".formula");
  p.tolerance = f.Number(q, "tolerance", path + ".tolerance", false);
  if (p.tolerance < 0) f.Fail(path + ".tolerance", "a tolerance >= 0");
  if (q.contains("tolerance_kind"))
    p.tolerance_kind = ParseToleranceKind(f.String(q, "tolerance_kind", path + ".tolerance_kind"),
                                          f, path + ".tolerance_kind");
  for (const char* key : {"beads", "profile"})
    if (q.contains(key)) {
      p.detail_key = key;
      p.detail = q[key];
    }
  return p;
}

}  // namespace

const char* ToleranceKindName(ToleranceKind kind) {
  switch (kind) {
    case ToleranceKind::kRelative:
      return "relative";
    case ToleranceKind::kAbsoluteCu:
      return "absolute_cu";
    case ToleranceKind::kInformative:
      return "informative";
  }
  return "?";
}

const PredictedQuantity* Prediction::Find(const std::string& quantity) const {
  for (const PredictedQuantity& q : predictions)
    if (q.quantity == quantity) return &q;
  return nullptr;
}

double Prediction::ValueOf(const std::string& quantity) const {
  const PredictedQuantity* q = Find(quantity);
  return q ? q->value : std::nan("");
}

double Prediction::InputValue(const std::string& name) const {
  for (const PredictionInput& i : inputs)
    if (i.name == name) return i.value;
  return std::nan("");
}

json Prediction::ToJson() const {
  json in = json::array(), out = json::array();
  for (const PredictionInput& i : inputs)
    in.push_back({{"name", i.name}, {"value", i.value}, {"unit", i.unit}, {"source", i.source}});
  for (const PredictedQuantity& q : predictions) {
    json j = {{"quantity", q.quantity},   {"value", q.value},
              {"unit", q.unit},           {"value_si", q.value_si},
              {"unit_si", q.unit_si},     {"formula", q.formula},
              {"tolerance", q.tolerance}, {"tolerance_kind", ToleranceKindName(q.tolerance_kind)}};
    if (!q.detail_key.empty()) j[q.detail_key] = q.detail;
    out.push_back(j);
  }
  return {{"schema", "owval.prediction/1"},
          {"predictor", predictor},
          {"scenario", scenario},
          {"configuration", configuration},
          {"omit_quarter_factor", omit_quarter_factor},
          {"track", track.ToJson()},
          {"inputs", in},
          {"predictions", out},
          {"notes", notes}};
}

Prediction Prediction::FromJson(const json& j, const std::string& file) {
  const Fields f(file);
  if (!j.is_object()) f.Fail("(top level)", "an object (owval predict -o FILE)");
  Prediction p;
  p.predictor = f.String(j, "predictor", "predictor");
  p.scenario = f.String(j, "scenario", "scenario");
  p.configuration = f.String(j, "configuration", "configuration");
  if (j.contains("omit_quarter_factor")) {
    if (!j["omit_quarter_factor"].is_boolean()) f.Fail("omit_quarter_factor", "true or false");
    p.omit_quarter_factor = j["omit_quarter_factor"].get<bool>();
  }
  if (!j.contains("track")) f.Fail("track", "an axis and a particle or group");
  p.track = Track::FromJson(j["track"], file);
  const json& inputs = f.Array(j, "inputs", "inputs");
  for (std::size_t k = 0; k < inputs.size(); ++k) {
    const std::string path = "inputs[" + std::to_string(k) + "]";
    if (!inputs[k].is_object()) f.Fail(path, "an object");
    p.inputs.push_back({f.String(inputs[k], "name", path + ".name", true),
                        f.Number(inputs[k], "value", path + ".value", true),
                        f.String(inputs[k], "unit", path + ".unit"),
                        f.String(inputs[k], "source", path + ".source")});
  }
  const json& quantities = f.Array(j, "predictions", "predictions");
  if (quantities.empty()) f.Fail("predictions", "a non-empty list");
  for (std::size_t k = 0; k < quantities.size(); ++k)
    p.predictions.push_back(
        QuantityFromJson(quantities[k], f, "predictions[" + std::to_string(k) + "]"));
  const json& notes = f.Array(j, "notes", "notes");
  for (std::size_t k = 0; k < notes.size(); ++k) {
    if (!notes[k].is_string()) f.Fail("notes[" + std::to_string(k) + "]", "a string");
    p.notes.push_back(notes[k].get<std::string>());
  }
  return p;
}

const ReconcileRow* Reconciliation::Find(const std::string& quantity) const {
  for (const ReconcileRow& r : rows)
    if (r.quantity == quantity) return &r;
  return nullptr;
}

json Reconciliation::ToJson() const {
  auto optional = [](const auto& v) { return v ? json(*v) : json(nullptr); };
  json out = json::array();
  for (const ReconcileRow& r : rows)
    out.push_back({{"quantity", r.quantity},
                   {"predicted", r.predicted},
                   {"unit", r.unit},
                   {"tolerance", r.tolerance},
                   {"tolerance_kind", ToleranceKindName(r.tolerance_kind)},
                   {"gap_kind", r.gap_in_cu ? "absolute_cu" : "relative"},
                   {"measured", optional(r.measured)},
                   {"gap", optional(r.gap)},
                   {"pass", optional(r.pass)},
                   {"hint", r.hint}});
  return {{"schema", "owval.reconcile/1"},
          {"predictor", predictor},
          {"scenario", scenario},
          {"signal", signal},
          {"frames", frames},
          {"rows", out},
          {"pass", pass}};
}

}  // namespace owval::predict
