#include "owval/predict/predict.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "owval/base/errors.hpp"
#include "owval/compare/signal_metrics.hpp"

namespace owval::predict {
namespace {

constexpr double kPi = 3.14159265358979323846;

nlohmann::json Input(const std::string& name, double value, const std::string& unit,
                     const std::string& source) {
  return {{"name", name}, {"value", value}, {"unit", unit}, {"source", source}};
}

nlohmann::json Quantity(const std::string& name, double value, const std::string& unit,
                        double si_value, const std::string& si_unit, const std::string& formula,
                        double tolerance, const std::string& tolerance_kind) {
  return {{"quantity", name},       {"value", value},
          {"unit", unit},           {"value_si", si_value},
          {"unit_si", si_unit},     {"formula", formula},
          {"tolerance", tolerance}, {"tolerance_kind", tolerance_kind}};
}

bool WormBody(float type) { return type > 2.05f && type < 2.25f; }

// One elastic particle e on one spring to an anchor: a harmonic oscillator along the spring, with
// Sibernetic's acceleration −Δr·k·f (k in s⁻², no mass) integrated by semi-implicit Euler.
nlohmann::json HarmonicSpring(const engine::SiberneticConfig& c, const engine::PhysicsConstants& k,
                              const PredictOptions& o) {
  const engine::Row4 spring = c.connection[0];
  const std::size_t anchor = static_cast<std::size_t>(spring[0]);
  const engine::Row4 e = c.position[0], a = c.position[anchor];
  const bool full = WormBody(e[3]) && WormBody(a[3]);
  const double factor = full || o.omit_quarter_factor ? 1.0 : k.non_worm_body_spring_factor;
  const double k_eff = k.elasticity_coefficient * factor;
  const double omega = std::sqrt(k_eff), dt = k.time_step_s, s = k.simulation_scale;
  const double period_continuous = 2 * kPi / omega;
  const double period = 2 * kPi / ((2 / dt) * std::asin(omega * dt / 2));
  const double sag_cu = std::abs(k.gravity[1]) / k_eff / s;
  const double equilibrium = a[1] - spring[1] - sag_cu;
  const double offset = e[1] - equilibrium;
  const double half_amplitude = std::abs(offset) / std::sqrt(1 - std::pow(omega * dt / 2, 2));
  nlohmann::json p;
  p["predictor"] = "harmonic_spring";
  p["inputs"] = {
      Input("anchor_y", a[1], "cu", "configuration [position] row " + std::to_string(anchor)),
      Input("start_y", e[1], "cu", "configuration [position] row 0"),
      Input("rest_length", spring[1], "cu", "configuration [connection] row 0"),
      Input("spring_factor", factor, "1",
            o.omit_quarter_factor ? "omitted on request (--no-quarter-factor)"
            : full                ? "both ends worm body (2.05 < type < 2.25): full stiffness"
                                  : "sphFluid.cl: 0.25 unless both ends are worm body (types " +
                         std::to_string(e[3]).substr(0, 4) + ", " +
                         std::to_string(a[3]).substr(0, 4) + ")"),
      Input("elasticity_coefficient", k.elasticity_coefficient, "s^-2",
            "default constant 4*1.5e-4/mass"),
      Input("time_step", dt, "s", "default constant"),
      Input("simulation_scale", s, "m/cu", "default constant"),
      Input("gravity_y", k.gravity[1], "m/s^2", "default constant")};
  p["predictions"] = {
      Quantity("zero_crossing_period", period, "s", period, "s",
               "T = 2*pi / ((2/dt) * asin(omega*dt/2)), omega = sqrt(k*f) (semi-implicit Euler); "
               "continuous: " +
                   std::to_string(period_continuous) + " s",
               0.003, "relative"),
      Quantity("half_amplitude", half_amplitude, "cu", half_amplitude * s, "m",
               "A = |y0 - y_eq| / sqrt(1 - (omega*dt/2)^2)", 0.01, "relative"),
      Quantity("equilibrium", equilibrium, "cu", equilibrium * s, "m",
               "y_eq = y_anchor - L0 - g/(k*f)/s", 0.01, "absolute_cu"),
      Quantity("gravity_sag", sag_cu, "cu", sag_cu * s, "m", "g/(k*f)/s", 0, "informative")};
  p["track"] = {{"particle", 0}, {"axis", "y"}};
  return p;
}

// One liquid particle falling from rest: contact when it comes within r0 of the floor's wall
// particles (where Ihmsen's wall weight starts), y_contact = y_wall + r0.
nlohmann::json FreeFall(const engine::SiberneticConfig& c, const engine::PhysicsConstants& k) {
  float floor_y = 1e30f;
  for (const auto& p : c.position)
    if (KindOf(p[3]) == ParticleKind::kBoundary) floor_y = std::min(floor_y, p[1]);
  const double y0 = c.position[0][1], contact_y = floor_y + k.r0_cu, g = std::abs(k.gravity[1]);
  const double drop_m = (y0 - contact_y) * k.simulation_scale;
  if (drop_m <= 0)
    throw InputError(c.source, 0, "free fall: the particle starts in contact with the floor");
  const double t = std::sqrt(2 * drop_m / g);
  nlohmann::json p;
  p["predictor"] = "free_fall";
  p["inputs"] = {Input("start_y", y0, "cu", "configuration [position] row 0"),
                 Input("floor_wall_y", floor_y, "cu", "lowest boundary particle in [position]"),
                 Input("r0", k.r0_cu, "cu", "default constant h/2"),
                 Input("gravity_y", k.gravity[1], "m/s^2", "default constant"),
                 Input("simulation_scale", k.simulation_scale, "m/cu", "default constant")};
  p["predictions"] = {Quantity("contact_time", t, "s", t, "s", "t = sqrt(2*(y0 - y_wall - r0)*s/g)",
                               0.02, "relative"),
                      Quantity("contact_height", contact_y, "cu", contact_y * k.simulation_scale,
                               "m", "y_wall + r0", 0, "informative")};
  p["track"] = {{"particle", 0}, {"axis", "y"}};
  return p;
}

std::string Number(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

}  // namespace

nlohmann::json Predict(const engine::SiberneticConfig& c, const engine::PhysicsConstants& k,
                       const PredictOptions& o) {
  const std::size_t elastic = c.elastic_count(), liquid = c.liquid_count();
  std::size_t springs = 0;
  for (const auto& row : c.connection) springs += row[0] >= 0;
  nlohmann::json p;
  if (elastic == 1 && springs == 1 && liquid == 0) {
    p = HarmonicSpring(c, k, o);
  } else if (elastic == 0 && liquid == 1) {
    p = FreeFall(c, k);
  } else {
    throw InputError(
        c.source, 0,
        "no analytic predictor for this configuration (" + std::to_string(elastic) + " elastic, " +
            std::to_string(liquid) + " liquid, " + std::to_string(springs) +
            " springs): expected one elastic particle on one spring, or one liquid particle");
  }
  p["schema"] = "owval.prediction/1";
  p["scenario"] = o.scenario;
  p["configuration"] = c.source;
  p["omit_quarter_factor"] = o.omit_quarter_factor;
  return p;
}

std::string PredictionMarkdown(const nlohmann::json& p) {
  std::ostringstream s;
  s << "## Prediction (" << p.value("predictor", "") << ") for " << p.value("scenario", "")
    << "\n\n";
  s << "| quantity | value | SI | formula |\n|---|---|---|---|\n";
  for (const auto& q : p["predictions"])
    s << "| " << q["quantity"].get<std::string>() << " | " << Number(q["value"]) << " "
      << q["unit"].get<std::string>() << " | " << Number(q["value_si"]) << " "
      << q["unit_si"].get<std::string>() << " | " << q["formula"].get<std::string>() << " |\n";
  s << "\n| input | value | source |\n|---|---|---|\n";
  for (const auto& i : p["inputs"])
    s << "| " << i["name"].get<std::string>() << " | " << Number(i["value"]) << " "
      << i["unit"].get<std::string>() << " | " << i["source"].get<std::string>() << " |\n";
  return s.str();
}

namespace {

std::optional<double> Measure(const std::string& quantity, const compare::SignalMetrics& m,
                              const std::vector<double>& t, const std::vector<double>& y,
                              const nlohmann::json& p) {
  if (quantity == "zero_crossing_period") return m.period_s;
  if (quantity == "half_amplitude") return m.half_amplitude;
  if (quantity == "equilibrium") return m.equilibrium;
  if (quantity == "contact_time") {
    double contact_y = 0;
    for (const auto& q : p["predictions"])
      if (q["quantity"] == "contact_height") contact_y = q["value"];
    for (std::size_t i = 1; i < y.size(); ++i)
      if (y[i] < contact_y)
        return t[i - 1] + (t[i] - t[i - 1]) * (y[i - 1] - contact_y) / (y[i - 1] - y[i]);
    return std::nullopt;
  }
  return std::nullopt;
}

std::string Hint(const std::string& quantity, double ratio, const compare::SignalMetrics& m) {
  if (quantity == "zero_crossing_period" &&
      (std::abs(ratio - 2) < 0.1 || std::abs(ratio - 0.5) < 0.05))
    return "period off by 2x: the 0.25 factor Sibernetic applies to springs not between two "
           "worm-body particles "
           "(2.05 < type < 2.25) quarters the stiffness";
  if (quantity == "contact_time" && ratio < 1)
    return "faster fall than free fall: missing buoyancy or an extra downward force";
  if (m.log_decrement && *m.log_decrement > 0.01)
    return "extra damping: viscous coupling (viscosity with neighbours or walls) removes energy";
  if (m.drift_per_s && m.period_s &&
      std::abs(*m.drift_per_s) * (m.window_end_s - m.window_start_s) > 0.01)
    return "steady drift of the cycle means: look for epsilon guards or a biased force";
  return "";
}

}  // namespace

nlohmann::json Reconcile(const nlohmann::json& p, const Trajectory& t) {
  std::size_t particle = 0;
  int axis = 1;
  try {
    particle = p.at("track").at("particle").get<std::size_t>();
    axis = ParseAxis(p.at("track").at("axis").get<std::string>());
  } catch (const nlohmann::json::exception& e) {
    throw InputError(std::string("prediction: expected a \"track\" with particle and axis: ") +
                     e.what());
  }
  const std::vector<double> y = ParticleSeries(t, particle, axis);
  const compare::SignalMetrics m = compare::MeasureSignal(t.time_s, y);
  nlohmann::json rows = nlohmann::json::array();
  bool pass = true;
  for (const auto& q : p.at("predictions")) {
    const std::string name = q.at("quantity"), kind = q.value("tolerance_kind", "relative");
    if (kind == "informative") continue;
    const double predicted = q.at("value");
    const auto measured = Measure(name, m, t.time_s, y, p);
    nlohmann::json row = {{"quantity", name},
                          {"predicted", predicted},
                          {"unit", q.value("unit", "")},
                          {"tolerance", q.value("tolerance", 0.0)},
                          {"tolerance_kind", kind}};
    if (!measured) {
      row["measured"] = nullptr;
      row["pass"] = false;
      row["hint"] = "could not be measured on this trajectory (too short, or no crossing)";
      pass = false;
      rows.push_back(row);
      continue;
    }
    const double gap =
        kind == "absolute_cu" ? *measured - predicted : (*measured - predicted) / predicted;
    const bool ok = std::abs(gap) <= q.value("tolerance", 0.0);
    row["measured"] = *measured;
    row["gap"] = gap;
    row["pass"] = ok;
    row["hint"] = ok ? "" : Hint(name, *measured / predicted, m);
    pass = pass && ok;
    rows.push_back(row);
  }
  return {{"schema", "owval.reconcile/1"},
          {"predictor", p.value("predictor", "")},
          {"rows", rows},
          {"pass", pass}};
}

std::string ReconcileMarkdown(const nlohmann::json& r) {
  std::ostringstream s;
  s << "## Reconciliation: " << (r["pass"].get<bool>() ? "PASS" : "FAIL") << "\n\n";
  s << "| quantity | predicted | measured | gap | tolerance | pass |\n|---|---|---|---|---|---|\n";
  for (const auto& row : r["rows"]) {
    const bool relative = row["tolerance_kind"] == "relative";
    auto gap = [&](double g) { return relative ? Number(g * 100) + "%" : Number(g) + " cu"; };
    s << "| " << row["quantity"].get<std::string>() << " | " << Number(row["predicted"]) << " "
      << row["unit"].get<std::string>() << " | "
      << (row["measured"].is_null() ? "n/a" : Number(row["measured"])) << " | "
      << (row.contains("gap") ? gap(row["gap"]) : "n/a") << " | " << gap(row["tolerance"]) << " | "
      << (row["pass"].get<bool>() ? "yes" : "NO") << " |\n";
  }
  for (const auto& row : r["rows"])
    if (!row["hint"].get<std::string>().empty())
      s << "\n- likely cause for " << row["quantity"].get<std::string>() << ": "
        << row["hint"].get<std::string>() << "\n";
  return s.str();
}

}  // namespace owval::predict
