#pragma once
// Finite-difference tests of a kernel's response (checklist item 7): a quantity measured from
// simulations, differentiated by central differences at two step sizes, against the derivative
// the physics predicts. Agreement at both steps shows the kernel responds as the model says.
#include <functional>
#include <nlohmann/json.hpp>
#include <string>

namespace owval::sgd {

struct FiniteDifferenceTest {
  std::string name;
  double at = 0;        // the point, in the variable being differentiated
  double step = 1e-2;   // central-difference half-step h (also run at h/2)
  double expected = 0;  // analytic derivative
  double relative_tolerance = 0.02;
  // Results:
  double derivative_h = 0, derivative_half_h = 0;
  double relative_error = 0;  // of the h/2 estimate
  bool pass = false;
  nlohmann::json ToJson() const;
};

// Evaluates f at at±h and at±h/2 (four evaluations) and fills the results.
void RunFiniteDifferenceTest(const std::function<double(double)>& f, FiniteDifferenceTest* test);

}  // namespace owval::sgd
