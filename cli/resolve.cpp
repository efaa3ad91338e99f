#include "resolve.hpp"

#include <filesystem>

#include "command.hpp"
#include "owval/base/errors.hpp"
#include "owval/scenarios/scenario.hpp"
#include "owval/sgd/engine_simulator.hpp"

namespace owval::cli {

engine::SiberneticConfig ResolveConfig(const std::string& name_or_path) {
  return scenarios::ResolveConfig(name_or_path, DataDir());
}

void SetConstantAssignment(const std::string& assignment, engine::PhysicsConstants* constants) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos) throw InputError("--set " + assignment + ": expected NAME=VALUE");
  double value = 0;
  try {
    std::size_t used = 0;
    value = std::stod(assignment.substr(eq + 1), &used);
    if (used != assignment.size() - eq - 1) throw std::invalid_argument("trailing");
  } catch (const std::exception&) {
    throw InputError("--set " + assignment + ": expected a number after '='");
  }
  sgd::SetConstant(constants, assignment.substr(0, eq), value);
}

}  // namespace owval::cli
