#pragma once
// JSON form of the phase-3 measurements, with units in the key names. Used by inspect,
// reconcile, compare and reports so that every tool prints the same keys.
#include <nlohmann/json.hpp>

#include "owval/compare/signal_metrics.hpp"

namespace owval::compare {

nlohmann::json ToJson(const SignalMetrics& metrics);

}  // namespace owval::compare
