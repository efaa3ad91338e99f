#include "owval/sgd/gradcheck.hpp"

namespace owval::sgd {

nlohmann::json GradCheckJson(const engine::GradCheckSummary& summary,
                             const engine::GradCheckOptions& options) {
  nlohmann::json tests = nlohmann::json::array();
  for (const engine::GradCheckTest& t : summary.tests)
    tests.push_back({{"name", t.name},
                     {"kernel", t.kernel},
                     {"step", t.epsilon},
                     {"direction", t.direction},
                     {"finite_difference", t.finite_difference},
                     {"analytic", t.analytic},
                     {"relative_error", t.relative_error},
                     {"tolerance", t.tolerance},
                     {"pass", t.pass}});
  return {{"tests", tests},
          {"pass", summary.pass},
          {"summary", summary.BriefReport()},
          {"seed", options.seed},
          {"directions", options.directions},
          {"scalar", "double"}};
}

}  // namespace owval::sgd
