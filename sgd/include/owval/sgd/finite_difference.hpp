#pragma once
// Finite-difference tests of a kernel's response (checklist item 7): a quantity measured from
// simulations, differentiated by central differences at two step sizes, against the derivative
// the physics predicts. Agreement at both steps shows the kernel responds as the model says.
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace owval::sgd {

// Its fields are fd_tests.json's (docs/schemas/fd_tests.schema.json), the names `owval
// gradcheck`'s tests use too: step, finite_difference, analytic, relative_error, tolerance, pass.
struct FiniteDifferenceTest {
  std::string name;
  double at = 0;         // the point, in the variable being differentiated
  double step = 1e-2;    // central-difference half-step h (also run at h/2)
  double analytic = 0;   // the derivative the physics predicts
  double tolerance = 0;  // relative, for the error and for the two steps' agreement
  // Results:
  double finite_difference_coarse = 0;  // at step h
  double finite_difference = 0;         // at step h/2: the estimate judged
  double relative_error = 0;            // of finite_difference against analytic
  bool pass = false;
  nlohmann::json ToJson() const;
};

// Evaluates f at at±h and at±h/2 (four evaluations) and fills the results.
void RunFiniteDifferenceTest(const std::function<double(double)>& f, FiniteDifferenceTest* test);

// fd_tests.json of these tests: {"tests": [...], "pass", "summary"}, as `owval gradcheck` writes
// (sgd/gradcheck.hpp), without its seed and directions.
nlohmann::json FiniteDifferenceTestsJson(const std::vector<FiniteDifferenceTest>& tests);

}  // namespace owval::sgd
