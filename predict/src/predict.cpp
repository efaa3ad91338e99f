#include "owval/predict/predict.hpp"

#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

#include "owval/base/errors.hpp"
#include "owval/base/format.hpp"
#include "prediction_parts.hpp"

namespace owval::predict {
namespace {

std::size_t SpringCount(const engine::SiberneticConfig& c) {
  std::size_t springs = 0;
  for (const auto& row : c.connection) springs += row[0] >= 0;
  return springs;
}

// Inputs drawn from constants that the caller changed (owval predict --set) are not Sibernetic's
// defaults any more: their source must say so, or the prediction would misreport where they came
// from.
void MarkChangedConstants(const engine::PhysicsConstants& k, std::vector<PredictionInput>* inputs) {
  const engine::PhysicsConstants d;
  const std::map<std::string, std::pair<double, double>> constants = {
      {"elasticity_coefficient", {k.elasticity_coefficient, d.elasticity_coefficient}},
      {"time_step", {k.time_step_s, d.time_step_s}},
      {"simulation_scale", {k.simulation_scale, d.simulation_scale}},
      {"gravity_y", {k.gravity[1], d.gravity[1]}},
      {"r0", {k.r0_cu, d.r0_cu}},
      {"h", {k.h_cu, d.h_cu}},
      {"mass", {k.mass_kg, d.mass_kg}},
      {"rest_density", {k.rest_density, d.rest_density}}};
  for (PredictionInput& input : *inputs) {
    const auto it = constants.find(input.name);
    if (it != constants.end() && it->second.first != it->second.second)
      input.source =
          "set by the caller (Sibernetic's default: " + FormatNumber(it->second.second, 7) + ")";
  }
}

}  // namespace

std::string ChoosePredictor(const engine::SiberneticConfig& c) {
  const std::size_t elastic = c.elastic_count(), liquid = c.liquid_count();
  const std::size_t springs = SpringCount(c);
  if (liquid == 0 && elastic == 1 && springs == 1) return "harmonic_spring";
  if (liquid == 0 && elastic >= 1 && springs >= elastic) return "hanging_chain";
  if (elastic == 0 && liquid == 1) return "free_fall";
  if (elastic == 0 && liquid > 1) return "hydrostatic_column";
  throw InputError(c.source, 0,
                   "no analytic predictor for this configuration (" + std::to_string(elastic) +
                       " elastic, " + std::to_string(liquid) + " liquid, " +
                       std::to_string(springs) +
                       " springs): expected elastic particles on springs and no liquid, or "
                       "liquid and no elastic particles");
}

namespace {

// A prediction that is NaN or infinite (a constant outside the formula's domain: time_step_s = 1
// puts omega*dt/2 past asin's, elasticity_coefficient = 0 gives no oscillation) cannot be
// reconciled: InputError naming the quantity and the constants that differ from the defaults.
void RequireFinite(const Prediction& p, const engine::SiberneticConfig& c,
                   const engine::PhysicsConstants& k) {
  for (const PredictedQuantity& q : p.predictions) {
    if (std::isfinite(q.value)) continue;
    const std::string changed = k.DifferencesFromDefaults();
    std::ostringstream msg;
    msg << "prediction " << q.quantity << " is not finite (" << q.value << ") "
        << (changed.empty() ? "for this configuration"
                            : "with the constants changed by --set: " + changed);
    throw InputError(c.source, 0, msg.str());
  }
}

}  // namespace

Prediction Predict(const engine::SiberneticConfig& c, const engine::PhysicsConstants& k,
                   const PredictOptions& o) {
  const std::string predictor = o.predictor.empty() ? ChoosePredictor(c) : o.predictor;
  Prediction p;
  if (predictor == "harmonic_spring" && c.elastic_count() == 1 && SpringCount(c) == 1) {
    p = internal::HarmonicSpring(c, k, o);
  } else if (predictor == "hanging_chain" && c.elastic_count() >= 1) {
    p = internal::HangingChain(c, k, o);
  } else if (predictor == "free_fall" && c.elastic_count() == 0 && c.liquid_count() == 1) {
    p = internal::FreeFall(c, k);
  } else if (predictor == "hydrostatic_column" && c.elastic_count() == 0) {
    p = internal::HydrostaticColumn(c, k);
  } else if (predictor == "hydrostatic_tank" && c.elastic_count() == 0) {
    p = internal::HydrostaticTank(c, k);
  } else if (predictor == "dam_break" && c.elastic_count() == 0) {
    p = internal::DamBreak(c, k);
  } else {
    throw InputError(c.source, 0,
                     "predictor '" + predictor + "' does not fit this configuration (" +
                         "it calls for " + ChoosePredictor(c) + ")");
  }
  MarkChangedConstants(k, &p.inputs);
  p.scenario = o.scenario;
  p.configuration = c.source;
  p.omit_quarter_factor = o.omit_quarter_factor;
  if (!c.physical_parameters.empty())
    p.notes.push_back(
        "the configuration's [physical parameters] block is ignored, as "
        "Sibernetic ignores it: Sibernetic's default constants are used");
  if (!k.DifferencesFromDefaults().empty())
    p.notes.push_back("constants differ from Sibernetic's defaults: " +
                      k.DifferencesFromDefaults());
  RequireFinite(p, c, k);
  return p;
}

std::string PredictionMarkdown(const Prediction& p) {
  std::ostringstream s;
  s << "## Prediction (" << p.predictor << ") for " << p.scenario << "\n\n";
  s << "| quantity | value | SI | gate | formula |\n|---|---|---|---|---|\n";
  for (const PredictedQuantity& q : p.predictions) {
    const std::string gate = q.tolerance_kind == internal::kInformative ? "informative"
                             : q.tolerance_kind == internal::kRelative
                                 ? "±" + FormatNumber(q.tolerance * 100, 7) + "%"
                                 : "±" + FormatNumber(q.tolerance, 7) + " cu";
    s << "| " << q.quantity << " | " << FormatNumber(q.value, 7) << " " << q.unit << " | "
      << FormatNumber(q.value_si, 7) << " " << q.unit_si << " | " << gate << " | " << q.formula
      << " |\n";
  }
  s << "\n| input | value | source |\n|---|---|---|\n";
  for (const PredictionInput& i : p.inputs)
    s << "| " << i.name << " | " << FormatNumber(i.value, 7) << " " << i.unit << " | " << i.source
      << " |\n";
  for (const std::string& note : p.notes) s << "\n- note: " << note << "\n";
  return s.str();
}

}  // namespace owval::predict
