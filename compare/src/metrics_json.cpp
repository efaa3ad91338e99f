#include "owval/compare/metrics_json.hpp"

#include <cstdio>

namespace owval::compare {
namespace {
nlohmann::json Optional(const std::optional<double>& value) {
  return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
}
}  // namespace

nlohmann::json ToJson(const SignalMetrics& m) {
  return {
      {"samples", m.samples},
      {"window_start_s", m.window_start_s},
      {"window_end_s", m.window_end_s},
      {"upward_crossings", m.upward_crossings},
      {"zero_crossing_period_s", Optional(m.period_s)},
      {"zero_crossing_period_spread_s", Optional(m.period_spread_s)},
      {"half_amplitude_cu", Optional(m.half_amplitude)},
      {"equilibrium_cu", m.equilibrium},
      {"drift_cu_per_s", Optional(m.drift_per_s)},
      {"log_decrement", Optional(m.log_decrement)},
      {"settling_time_s", Optional(m.settling_time_s)},
      {"initial_value_cu", m.initial_value},
      {"minimum_cu", m.minimum},
      {"time_of_minimum_s", m.time_of_minimum_s},
      {"time_of_maximum_s", m.time_of_maximum_s},
      {"maximum_cu", m.maximum},
      {"final_value_cu", m.final_value},
      {"over_whole_cycles", m.whole_cycles},
  };
}

namespace {

std::string Ms(const std::optional<double>& s) {
  char b[64];
  if (!s) return "n/a";
  std::snprintf(b, sizeof b, "%.6g ms", *s * 1e3);
  return b;
}

std::string Cu(const std::optional<double>& v, const char* unit = "cu") {
  char b[64];
  if (!v) return "n/a";
  std::snprintf(b, sizeof b, "%.6g %s", *v, unit);
  return b;
}

// printf into a string: the table's lines are fixed-width columns.
template <typename... Args>
std::string Line(const char* format, Args... args) {
  char b[256];
  std::snprintf(b, sizeof b, format, args...);
  return b;
}

}  // namespace

std::string ToText(const SignalMetrics& m, const std::string& subject) {
  std::string t = Line("signal: %s, %zu samples, t = %.6g .. %.6g s\n\n", subject.c_str(),
                       m.samples, m.window_start_s, m.window_end_s);
  t += Line("%-26s %s\n", "zero-crossing period", Ms(m.period_s).c_str());
  t += Line("%-26s %zu upward, spread %s\n", "  crossings", m.upward_crossings,
            Ms(m.period_spread_s).c_str());
  t += Line("%-26s %s%s\n", "half-amplitude", Cu(m.half_amplitude).c_str(),
            m.whole_cycles ? "" : " (no whole cycle: half the range)");
  t += Line("%-26s %.6g cu%s\n", "equilibrium", m.equilibrium,
            m.whole_cycles ? "" : " (window mean)");
  t += Line("%-26s %s\n", "drift", Cu(m.drift_per_s, "cu/s").c_str());
  t += Line("%-26s %s\n", "logarithmic decrement", Cu(m.log_decrement, "").c_str());
  t += Line("%-26s %s\n", "settling time (2% band)", Ms(m.settling_time_s).c_str());
  t += Line("%-26s initial %.6g, final %.6g cu\n", "values", m.initial_value, m.final_value);
  t += Line("%-26s %.6g cu at %.6g ms .. %.6g cu at %.6g ms\n", "range (min .. max)", m.minimum,
            m.time_of_minimum_s * 1e3, m.maximum, m.time_of_maximum_s * 1e3);
  return t;
}

}  // namespace owval::compare
