#include "resolve.hpp"

#include <filesystem>
#include <sstream>

#include "command.hpp"
#include "owval/base/errors.hpp"
#include "owval/engine/constants.hpp"
#include "owval/scenarios/scenario.hpp"

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
  engine::SetConstant(constants, assignment.substr(0, eq), value);
}

Trajectory ReadTrajectoryArgument(const std::string& path, const std::string& layout,
                                  TextReadReport* report) {
  TextReadOptions options;
  options.layout = ParseLayout(layout);
  options.quiet = Flags().quiet;
  return ReadTrajectory(path, options, report);
}

std::unique_ptr<FrameSource> OpenTrajectoryArgument(const std::string& path,
                                                    const std::string& layout,
                                                    TextReadReport* report) {
  TextReadOptions options;
  options.layout = ParseLayout(layout);
  options.quiet = Flags().quiet;
  return OpenFrameSource(path, options, report);
}

std::vector<std::size_t> ParseIndexList(const std::string& text, const std::string& flag) {
  std::vector<std::size_t> indices;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    try {
      std::size_t used = 0;
      indices.push_back(std::stoul(item, &used));
      if (used != item.size()) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      throw InputError(flag + ": expected comma-separated frame indices, found '" + item + "'");
    }
  }
  return indices;
}

}  // namespace owval::cli
