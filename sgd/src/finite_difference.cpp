#include "owval/sgd/finite_difference.hpp"

#include <cmath>

namespace owval::sgd {

void RunFiniteDifferenceTest(const std::function<double(double)>& f, FiniteDifferenceTest* t) {
  const double h = t->step;
  t->derivative_h = (f(t->at + h) - f(t->at - h)) / (2 * h);
  t->derivative_half_h = (f(t->at + h / 2) - f(t->at - h / 2)) / h;
  t->relative_error =
      std::abs(t->derivative_half_h - t->expected) / std::max(std::abs(t->expected), 1e-300);
  const double consistency =
      std::abs(t->derivative_h - t->derivative_half_h) / std::max(std::abs(t->expected), 1e-300);
  t->pass = std::isfinite(t->relative_error) && t->relative_error < t->relative_tolerance &&
            consistency < t->relative_tolerance;
}

nlohmann::json FiniteDifferenceTest::ToJson() const {
  return {{"name", name},
          {"at", at},
          {"step", step},
          {"expected", expected},
          {"derivative_h", derivative_h},
          {"derivative_half_h", derivative_half_h},
          {"relative_error", relative_error},
          {"relative_tolerance", relative_tolerance},
          {"pass", pass}};
}

}  // namespace owval::sgd
