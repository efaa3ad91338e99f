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

EnvironmentError::EnvironmentError(const std::string& message)
    : std::runtime_error(OneLine(message)) {}

SimulationError::SimulationError(const std::string& message)
    : std::runtime_error(OneLine(message)) {}

}  // namespace owval
