#include "owval/sgd/finite_difference.hpp"

#include <algorithm>
#include <cmath>

namespace owval::sgd {

void RunFiniteDifferenceTest(const std::function<double(double)>& f, FiniteDifferenceTest* t) {
  const double h = t->step;
  t->finite_difference_coarse = (f(t->at + h) - f(t->at - h)) / (2 * h);
  t->finite_difference = (f(t->at + h / 2) - f(t->at - h / 2)) / h;
  const double scale = std::max(std::abs(t->analytic), 1e-300);
  t->relative_error = std::abs(t->finite_difference - t->analytic) / scale;
  const double consistency = std::abs(t->finite_difference_coarse - t->finite_difference) / scale;
  t->pass = std::isfinite(t->relative_error) && t->relative_error < t->tolerance &&
            consistency < t->tolerance;
}

nlohmann::json FiniteDifferenceTest::ToJson() const {
  return {{"name", name},
          {"at", at},
          {"step", step},
          {"analytic", analytic},
          {"finite_difference_coarse", finite_difference_coarse},
          {"finite_difference", finite_difference},
          {"relative_error", relative_error},
          {"tolerance", tolerance},
          {"pass", pass}};
}

nlohmann::json FiniteDifferenceTestsJson(const std::vector<FiniteDifferenceTest>& tests) {
  nlohmann::json list = nlohmann::json::array();
  std::size_t passed = 0;
  for (const FiniteDifferenceTest& t : tests) {
    list.push_back(t.ToJson());
    passed += t.pass;
  }
  return {{"tests", list},
          {"pass", !tests.empty() && passed == tests.size()},
          {"summary", std::to_string(passed) + "/" + std::to_string(tests.size()) +
                          " finite-difference tests pass"}};
}

}  // namespace owval::sgd
