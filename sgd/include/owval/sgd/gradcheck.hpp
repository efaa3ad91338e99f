#pragma once
// The fd_tests.json of `owval gradcheck` (the PR checklist's item 7 input, docs/checklist.md):
//   {"tests": [{"name", "kernel", "epsilon", "direction", "finite_difference", "analytic",
//               "relative_error", "tolerance", "pass"}...], "pass", "summary", "seed"}
#include <nlohmann/json.hpp>

#include "owval/engine/gradient.hpp"

namespace owval::sgd {

nlohmann::json GradCheckJson(const engine::GradCheckSummary& summary,
                             const engine::GradCheckOptions& options);

}  // namespace owval::sgd
