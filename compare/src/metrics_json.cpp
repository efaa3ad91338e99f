#include "owval/compare/metrics_json.hpp"

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

}  // namespace owval::compare
