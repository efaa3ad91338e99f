#pragma once
// JSON and text forms of the phase-3 measurements, with units in the key names. Used by inspect,
// reconcile, compare and reports so that every tool prints the same keys.
#include <nlohmann/json.hpp>
#include <string>

#include "owval/compare/signal_metrics.hpp"

namespace owval::compare {

nlohmann::json ToJson(const SignalMetrics& metrics);

// The table `owval inspect` prints: "signal: SUBJECT, N samples, ..." then one aligned line per
// measurement (period, crossings, half-amplitude, equilibrium, drift, damping, settling, range).
std::string ToText(const SignalMetrics& metrics, const std::string& subject);

}  // namespace owval::compare
