#pragma once
// The fd_tests.json of `owval gradcheck` (the PR checklist's item 7 input, docs/checklist.md):
//   {"tests": [{"name", "kernel", "step", "direction", "finite_difference", "analytic",
//               "relative_error", "tolerance", "pass"}...], "pass", "summary", "seed", ...}
// Its tests carry the fields every fd_tests.json test has (sgd/finite_difference.hpp); "step"
// is the central difference's epsilon.
#include <nlohmann/json.hpp>

#include "owval/engine/gradient.hpp"

namespace owval::sgd {

nlohmann::json GradCheckJson(const engine::GradCheckSummary& summary,
                             const engine::GradCheckOptions& options);

}  // namespace owval::sgd
