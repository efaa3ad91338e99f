// Phase 3: each predicted quantity measured on the tracked signal (compare::MeasureSignal), the
// gap, and the likely cause of a gap that is too large.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <optional>
#include <sstream>

#include "owval/base/errors.hpp"
#include "owval/base/format.hpp"
#include "owval/base/number_text.hpp"
#include "owval/compare/signal_metrics.hpp"
#include "owval/predict/predict.hpp"
#include "owval/trajectory/track.hpp"
#include "prediction_parts.hpp"

namespace owval::predict {
namespace {

struct Signal {
  std::string description;
  std::vector<double> values;
  compare::SignalMetrics metrics;
};

Signal TrackedSignal(const Prediction& p, FrameSource& t) {
  Signal s;
  s.values = p.track.Series(t);
  s.description = p.track.Describe();
  s.metrics = compare::MeasureSignal(t.header().time_s, s.values);
  return s;
}

// Mean over the last 10% of frames (at least one): the settled value of a resting system.
double FinalMean(const std::vector<double>& v) {
  const std::size_t n = std::max<std::size_t>(1, v.size() / 10);
  double sum = 0;
  for (std::size_t i = v.size() - n; i < v.size(); ++i) sum += v[i];
  return sum / double(n);
}

std::optional<double> CrossingTime(const std::vector<double>& t, const std::vector<double>& y,
                                   double level) {
  for (std::size_t i = 1; i < y.size(); ++i)
    if (y[i] < level && y[i - 1] >= level)
      return t[i - 1] + (t[i] - t[i - 1]) * (y[i - 1] - level) / (y[i - 1] - y[i]);
  return std::nullopt;
}

// Frame f's pressure (the frame read with its fields), or null when the trajectory has none.
const float* PressureOf(const FrameRef& x) {
  const Trajectory& t = x.trajectory;
  return t.has_pressure() ? &t.pressure[x.frame * t.particle_count()] : nullptr;
}

// Mean pressure of the liquid particles that start in the bottom layer, over the last 10% of
// frames; empty when the trajectory carries no pressure.
std::optional<double> BottomPressure(FrameSource& t, double r0_cu) {
  if (t.frame_count() == 0) return std::nullopt;
  t.ReadFields();
  const FrameRef first = t.Frame(0);
  const std::vector<std::size_t> liquid = GroupIndices(t.header(), "liquid");
  if (!PressureOf(first) || liquid.empty()) return std::nullopt;
  double bottom = 1e30;
  for (std::size_t i : liquid)
    bottom = std::min(bottom, double(first.trajectory.coordinate(first.frame, i, 1)));
  std::vector<std::size_t> layer;  // the bottom layer at frame 0, in particle order
  for (std::size_t i : liquid)
    if (first.trajectory.coordinate(first.frame, i, 1) < bottom + r0_cu / 2) layer.push_back(i);
  std::vector<double> series;
  for (std::size_t f = 0; f < t.frame_count(); ++f) {
    const float* pressure = PressureOf(t.Frame(f));
    double sum = 0;
    for (std::size_t i : layer) sum += pressure[i];
    series.push_back(sum / double(layer.size()));
  }
  return FinalMean(series);
}

// hydrostatic_tank: per frame, over the liquid within half a spacing of mid-depth (each frame's
// positions), `value` of the particles' heights and pressures (empty: no such particle then);
// averaged over the last 10% of the frames that have one. Empty without pressure.
std::optional<double> MidDepthSeriesMean(
    FrameSource& t, const Prediction& p,
    const std::function<std::optional<double>(const std::vector<std::pair<double, float>>&)>&
        value) {
  if (t.frame_count() == 0) return std::nullopt;
  t.ReadFields();
  if (!PressureOf(t.Frame(0))) return std::nullopt;
  const double mid = p.InputValue("mid_depth_y"), half = 0.5 * p.InputValue("lattice_spacing");
  const std::vector<std::size_t> liquid = GroupIndices(t.header(), "liquid");
  std::vector<double> series;
  std::vector<std::pair<double, float>> at_mid;  // (y, pressure), in particle order
  for (std::size_t f = 0; f < t.frame_count(); ++f) {
    const FrameRef x = t.Frame(f);
    const float* pressure = PressureOf(x);
    at_mid.clear();
    for (std::size_t i : liquid) {
      const double y = x.trajectory.coordinate(x.frame, i, 1);
      if (std::abs(y - mid) < half) at_mid.push_back({y, pressure[i]});
    }
    if (const auto v = value(at_mid)) series.push_back(*v);
  }
  if (series.empty()) return std::nullopt;
  return FinalMean(series);
}

// hydrostatic_tank: mean pressure of the liquid within half a spacing of mid-depth (each
// frame's positions), averaged over the last 10% of frames.
std::optional<double> MidDepthPressure(FrameSource& t, const Prediction& p) {
  return MidDepthSeriesMean(
      t, p, [](const std::vector<std::pair<double, float>>& at) -> std::optional<double> {
        double sum = 0;
        for (const auto& [y, pressure] : at) sum += pressure;
        if (at.empty()) return std::nullopt;
        return sum / double(at.size());
      });
}

// hydrostatic_tank: the same particles' root-mean-square error against the profile at their
// own height, p(y) = p_mid (H - y)/(H - y_mid), over p_mid: the particle-to-particle error
// that the mean hides. Averaged over the last 10% of frames.
std::optional<double> MidDepthPressureError(FrameSource& t, const Prediction& p) {
  return MidDepthSeriesMean(
      t, p, [&](const std::vector<std::pair<double, float>>& at) -> std::optional<double> {
        // Read here, as before: only once the trajectory is known to carry pressure.
        const double mid = p.InputValue("mid_depth_y"), surface = p.InputValue("free_surface_y");
        const double p_mid = p.ValueOf("mid_depth_pressure");
        double sum = 0;
        for (const auto& [y, pressure] : at) {
          const double error = pressure - p_mid * (surface - y) / (surface - mid);
          sum += error * error;
        }
        if (at.empty()) return std::nullopt;
        return std::sqrt(sum / double(at.size())) / p_mid;
      });
}

// dam_break: Z = (front - wall face)/a at T, the front the k-th largest liquid x (k = 0.2% of
// the liquid, at least 1: a few splashed particles do not make the front) + half a spacing,
// interpolated linearly between frames; empty past the trajectory's end.
std::optional<double> SurgeFront(FrameSource& t, const Prediction& p, double big_t) {
  const double when = big_t * p.InputValue("time_unit"), a = p.InputValue("column_width_a");
  const double wall = p.InputValue("wall_face_x"), half = 0.5 * p.InputValue("lattice_spacing");
  const std::vector<std::size_t> liquid = GroupIndices(t.header(), "liquid");
  if (liquid.empty() || !(a > 0)) return std::nullopt;
  const std::size_t k = std::max<std::size_t>(1, liquid.size() / 500);
  const auto front = [&](std::size_t f) {
    const FrameRef x = t.Frame(f);
    std::vector<double> xs;
    for (std::size_t i : liquid) xs.push_back(x.trajectory.coordinate(x.frame, i, 0));
    std::nth_element(xs.begin(), xs.begin() + (k - 1), xs.end(), std::greater<double>());
    return (xs[k - 1] + half - wall) / a;
  };
  const std::vector<double>& time_s = t.header().time_s;
  for (std::size_t f = 1; f < t.frame_count(); ++f)
    if (time_s[f] >= when && time_s[f - 1] <= when) {
      const double u = (when - time_s[f - 1]) / (time_s[f] - time_s[f - 1]);
      const double before = front(f - 1), after = front(f);
      return before + u * (after - before);
    }
  return std::nullopt;
}

// T of a "..._at_T_<T>" quantity name from prediction.json: std::stod threw std::invalid_argument
// on an edited name ("surge_front_Z_at_T_x"), a message naming neither file nor quantity.
double TimeInQuantityName(const std::string& q, std::size_t prefix) {
  if (const std::optional<double> t = ParseDecimal(std::string_view(q).substr(prefix))) return *t;
  throw InputError("prediction quantity " + q + ": expected a time in seconds after its '_at_T_'");
}

std::optional<double> Measure(const std::string& q, const Signal& s, FrameSource& t,
                              const Prediction& p) {
  if (q == "mid_depth_pressure") return MidDepthPressure(t, p);
  if (q == "mid_depth_pressure_rms_error") return MidDepthPressureError(t, p);
  const std::string front = "surge_front_Z_at_T_";
  if (q.rfind(front, 0) == 0) return SurgeFront(t, p, TimeInQuantityName(q, front.size()));
  const std::string ko_front = "koshizuka_oka_front_Z_at_T_";
  if (q.rfind(ko_front, 0) == 0) return SurgeFront(t, p, TimeInQuantityName(q, ko_front.size()));
  const compare::SignalMetrics& m = s.metrics;
  if (q == "zero_crossing_period" || q == "period_continuous" || q == "fundamental_period")
    return m.period_s;
  if (q == "half_amplitude") return m.half_amplitude;
  if (q == "equilibrium") return m.equilibrium;
  if (q == "tip_sag") return m.initial_value - m.equilibrium;
  if (q == "contact_time" || q == "contact_time_continuous")
    return CrossingTime(t.header().time_s, s.values, p.ValueOf("contact_height"));
  if (q == "centroid_equilibrium") return FinalMean(s.values);
  if (q == "bottom_pressure") return BottomPressure(t, engine::PhysicsConstants{}.r0_cu);
  return std::nullopt;
}

bool Near(double a, double b, double relative) { return std::abs(a / b - 1) < relative; }

std::string QuantityHint(const std::string& q, double measured, double predicted,
                         const Prediction& p) {
  const double ratio = measured / predicted;
  if (q == "zero_crossing_period") {
    if (Near(ratio, 2, 0.05) || Near(ratio, 0.5, 0.05))
      return "period off by 2x: the 0.25 factor Sibernetic applies (sphFluid.cl) to springs not "
             "between two worm-body particles (2.05 < type < 2.25) quarters the stiffness";
    if (Near(measured, p.ValueOf("period_continuous"), 2e-4))
      return "the measurement follows the continuous-time period: not semi-implicit Euler, or "
             "a much smaller time step";
    return "stiffness or time step differ from the prediction's: check elasticityCoefficient, "
           "the spring's types and dt";
  }
  if (q == "equilibrium") {
    const double sag = p.ValueOf("gravity_sag");
    if (std::isfinite(sag) && Near(std::abs(measured - predicted), sag, 0.2))
      return "equilibrium shifted by one gravity sag: gravity missing or counted twice";
    if (std::isfinite(sag))
      return "the gravity sag g/(k*f)/s scales with 1/stiffness: a stiffness error (see the "
             "period) moves the equilibrium";
  }
  if (q == "contact_time")
    return ratio < 1 ? "faster than free fall: missing buoyancy or an extra downward force"
                     : "slower than free fall: drag (viscous coupling with neighbours or walls) "
                       "or weaker gravity";
  if (q == "centroid_equilibrium" && measured < predicted &&
      p.ValueOf("initial_bulk_density") < 0.99 * p.InputValue("rest_density"))
    return "the liquid starts under-dense (" + std::to_string(p.ValueOf("initial_bulk_density")) +
           " kg/m^3 < rho0): Sibernetic clamps pressure increments at >= 0, so nothing holds "
           "the column up until it compacts; start the lattice at the rest spacing " +
           std::to_string(p.ValueOf("rest_lattice_spacing")) + " cu";
  if (q == "centroid_equilibrium")
    return measured < predicted
               ? "the column compresses: density errors above 1% (few PCISPH iterations; "
                 "particle deficiency lets the free-surface layers sink)"
               : "the column expands: particles start closer than the rest spacing "
                 "(m/rho0)^(1/3), or the pressure overshoots";
  return "";
}

std::string SignalHint(const compare::SignalMetrics& m) {
  if (m.log_decrement && *m.log_decrement > 0.01)
    return "extra damping (log decrement " + std::to_string(*m.log_decrement) +
           "): viscous coupling with neighbours or walls removes energy";
  if (m.drift_per_s && std::abs(*m.drift_per_s) * (m.window_end_s - m.window_start_s) > 0.01)
    return "steady drift of the cycle means: look for epsilon guards (r != 0, density floors) "
           "or a biased force";
  return "";
}

double Tolerance(const PredictedQuantity& q, const ReconcileOptions& o) {
  const auto it = o.tolerances.find(q.quantity);
  if (it != o.tolerances.end()) return it->second;
  return o.tolerance ? *o.tolerance : q.tolerance;
}

ReconcileRow Row(const PredictedQuantity& q, const std::optional<double>& measured,
                 const ReconcileOptions& o) {
  ReconcileRow row;
  const bool gated = q.tolerance_kind != ToleranceKind::kInformative;
  row.quantity = q.quantity;
  row.predicted = q.value;
  row.unit = q.unit;
  row.tolerance = gated ? Tolerance(q, o) : 0.0;
  row.tolerance_kind = q.tolerance_kind;
  // Positions gap in cu, everything else relative to the prediction.
  row.gap_in_cu = q.tolerance_kind == ToleranceKind::kAbsoluteCu ||
                  (q.tolerance_kind == ToleranceKind::kInformative && q.unit == "cu");
  // An informative quantity predicted as 0 (an error that should vanish): the gap is the
  // measured value itself.
  const bool absolute = row.gap_in_cu || (!gated && q.value == 0);
  if (measured) {
    row.measured = *measured;
    row.gap = absolute ? *measured - q.value : (*measured - q.value) / q.value;
  }
  if (gated) row.pass = measured && std::abs(*row.gap) <= row.tolerance;
  if (gated && !measured)
    row.hint = "could not be measured on this trajectory (too short, or no crossing)";
  return row;
}

}  // namespace

Reconciliation Reconcile(const Prediction& p, const Trajectory& trajectory,
                         const ReconcileOptions& o) {
  const auto frames = MemoryFrameSource(trajectory);
  return Reconcile(p, *frames, o);
}

void CheckTolerances(const Prediction& p, const ReconcileOptions& o) {
  std::string gated;
  for (const PredictedQuantity& q : p.predictions)
    if (q.tolerance_kind != ToleranceKind::kInformative)
      gated += (gated.empty() ? "" : ", ") + q.quantity;
  for (const auto& [name, value] : o.tolerances) {
    const PredictedQuantity* q = p.Find(name);
    if (q && q->tolerance_kind != ToleranceKind::kInformative) continue;
    throw InputError("--tolerance " + name + "=...: " +
                     (q ? "quantity " + name + " is informative, not gated"
                        : "unknown quantity '" + name + "'") +
                     "; the prediction's gated quantities are " + (gated.empty() ? "none" : gated));
  }
}

Reconciliation Reconcile(const Prediction& p, FrameSource& t, const ReconcileOptions& o) {
  CheckTolerances(p, o);
  const Signal s = TrackedSignal(p, t);
  Reconciliation r;
  r.predictor = p.predictor;
  r.scenario = p.scenario;
  r.signal = s.description;
  r.frames = t.frame_count();
  for (const PredictedQuantity& q : p.predictions) {
    ReconcileRow row = Row(q, Measure(q.quantity, s, t, p), o);
    if (row.pass == false) {
      r.pass = false;
      if (row.measured) row.hint = QuantityHint(q.quantity, *row.measured, row.predicted, p);
      if (row.hint.empty()) row.hint = SignalHint(s.metrics);
    }
    r.rows.push_back(row);
  }
  return r;
}

std::string ReconcileMarkdown(const Reconciliation& r) {
  std::ostringstream s;
  s << "## Reconciliation (" << r.predictor << ", " << r.signal
    << "): " << (r.pass ? "PASS" : "FAIL") << "\n\n";
  s << "| quantity | predicted | measured | gap | tolerance | pass |\n|---|---|---|---|---|---|\n";
  for (const ReconcileRow& row : r.rows) {
    auto gap = [&](double g) {
      return row.gap_in_cu ? FormatNumber(g, 7) + " cu" : FormatNumber(g * 100, 7) + "%";
    };
    s << "| " << row.quantity << " | " << FormatNumber(row.predicted, 7) << " " << row.unit << " | "
      << (row.measured ? FormatNumber(*row.measured, 7) : "n/a") << " | "
      << (row.gap ? gap(*row.gap) : "n/a") << " | "
      << (row.tolerance_kind == ToleranceKind::kInformative ? "-" : gap(row.tolerance)) << " | "
      << (!row.pass   ? "info"
          : *row.pass ? "yes"
                      : "NO")
      << " |\n";
  }
  for (const ReconcileRow& row : r.rows)
    if (!row.hint.empty()) s << "\n- likely cause for " << row.quantity << ": " << row.hint << "\n";
  return s.str();
}

void ReconcileOptions::AddTolerance(const std::string& text) {
  const auto eq = text.find('=');
  const std::string number = eq == std::string::npos ? text : text.substr(eq + 1);
  const std::optional<double> parsed = ParseDecimal(number);
  if (!parsed || !(*parsed >= 0))
    throw InputError("--tolerance " + text + ": expected a number >= 0 or QUANTITY=NUMBER");
  const double value = *parsed;
  if (eq == 0)
    throw InputError("--tolerance " + text + ": expected QUANTITY=NUMBER, the quantity is missing");
  if (eq == std::string::npos)
    tolerance = value;
  else
    tolerances[text.substr(0, eq)] = value;
}

}  // namespace owval::predict
