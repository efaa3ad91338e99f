#pragma once
// Errors that reach the user. Every library throws InputError for bad input (a file that does
// not parse, a wrong count, a NaN) so that the CLI can print one line and exit with code 2.
#include <cstddef>
#include <stdexcept>
#include <string>

namespace owval {

// Bad input: a file or an argument that cannot be used. what() is one line of the form
// "FILE:LINE: message" (LINE omitted when 0), ready to print: made one line of printable ASCII of
// at most 300 characters by OneLine() (one_line.hpp), whatever the file fed into the message.
class InputError : public std::runtime_error {
 public:
  InputError(const std::string& file, std::size_t line, const std::string& message);
  explicit InputError(const std::string& message);

  const std::string& file() const { return file_; }
  std::size_t line() const { return line_; }

 private:
  std::string file_;
  std::size_t line_ = 0;
};

// The simulation itself failed on valid input: a NaN or a diverging particle. One line naming
// the step, the particle and the quantity; the CLI exits with code 1 (kExitGateFailed), not 2.
class SimulationError : public std::runtime_error {
 public:
  explicit SimulationError(const std::string& message);
};

// Exit codes shared by every command (design notes §5).
// kExitInterrupted: a run stopped by SIGINT (128 + the signal, the shell's convention; SIGTERM
// gives 143), after leaving a partial trajectory and a checkpoint.
enum ExitCode : int {
  kExitPass = 0,
  kExitGateFailed = 1,
  kExitBadInput = 2,
  kExitInterrupted = 130
};

}  // namespace owval
