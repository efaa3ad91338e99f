#include "owval/base/errors.hpp"

#include "owval/base/one_line.hpp"

namespace owval {
namespace {
std::string Locate(const std::string& file, std::size_t line, const std::string& message) {
  if (file.empty()) return OneLine(message);
  if (line == 0) return OneLine(file + ": " + message);
  return OneLine(file + ":" + std::to_string(line) + ": " + message);
}
}  // namespace

InputError::InputError(const std::string& file, std::size_t line, const std::string& message)
    : std::runtime_error(Locate(file, line, message)), file_(file), line_(line) {}

InputError::InputError(const std::string& message) : std::runtime_error(OneLine(message)) {}

NonFiniteTrajectoryError::NonFiniteTrajectoryError(const std::string& file, std::size_t line,
                                                   const std::string& message)
    : InputError(file, line, message + ": the simulation that wrote this file failed") {}

EnvironmentError::EnvironmentError(const std::string& message)
    : std::runtime_error(OneLine(message)) {}

std::string DescribeFilesystemError(const std::filesystem::filesystem_error& error) {
  // what() is "filesystem error: OPERATION: REASON [PATH1] [PATH2]": keep OPERATION: REASON.
  std::string what = error.what();
  const std::string prefix = "filesystem error: ";
  if (what.rfind(prefix, 0) == 0) what.erase(0, prefix.size());
  if (const auto bracket = what.find(" ["); bracket != std::string::npos) what.erase(bracket);
  const std::string path = error.path1().string();
  return OneLine(path.empty() ? what : path + ": " + what);
}

SimulationError::SimulationError(const std::string& message)
    : std::runtime_error(OneLine(message)) {}

}  // namespace owval
