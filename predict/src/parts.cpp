#include <cmath>
#include <string>

#include "prediction_parts.hpp"

namespace owval::predict::internal {

PredictionInput Input(const std::string& name, double value, const std::string& unit,
                      const std::string& source) {
  return {name, value, unit, source};
}

PredictedQuantity Quantity(const std::string& name, double value, const std::string& unit,
                           double value_in_si, const std::string& si_unit,
                           const std::string& formula, double tolerance,
                           ToleranceKind tolerance_kind) {
  PredictedQuantity q;
  q.quantity = name;
  q.value = value;
  q.unit = unit;
  q.value_si = value_in_si;
  q.unit_si = si_unit;
  q.formula = formula;
  q.tolerance = tolerance;
  q.tolerance_kind = tolerance_kind;
  return q;
}

std::string ConfigSource(const engine::SiberneticConfig& c, Section section, std::size_t row) {
  // Layout: [physical parameters] block (if any), "[simulation box]" + 6 lines, "[position]" +
  // N rows, "[velocity]" + N rows, "[connection]" + rows.
  const std::size_t params = c.physical_parameters.empty() ? 0 : 1 + c.physical_parameters.size();
  const std::size_t n = c.particle_count();
  std::size_t line = params + 9 + row;
  const char* name = "[position]";
  if (section == Section::kVelocity) {
    line = params + 10 + n + row;
    name = "[velocity]";
  } else if (section == Section::kConnection) {
    line = params + 11 + 2 * n + row;
    name = "[connection]";
  }
  return "configuration line " + std::to_string(line) + " (" + name + " row " +
         std::to_string(row) + ")";
}

std::string DefaultSource(const std::string& what) {
  return "Sibernetic default constant (inc/owPhysicsConstant.h): " + what;
}

bool WormBody(float type) { return type > 2.05f && type < 2.25f; }

double SpringFactor(float type_a, float type_b, const engine::PhysicsConstants& k,
                    const PredictOptions& o) {
  if (o.omit_quarter_factor || (WormBody(type_a) && WormBody(type_b))) return 1.0;
  return k.non_worm_body_spring_factor;
}

double SymplecticEulerPeriod(double omega, double dt_s) {
  // Semi-implicit Euler rotates phase space by 2*asin(omega*dt/2) per step (stable for
  // omega*dt < 2), so the discrete angular frequency is (2/dt)*asin(omega*dt/2).
  return 2 * kPi / ((2 / dt_s) * std::asin(omega * dt_s / 2));
}

}  // namespace owval::predict::internal
