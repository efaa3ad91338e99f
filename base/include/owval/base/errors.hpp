#pragma once
// Errors that reach the user. Every library throws InputError for bad input (a file that does
// not parse, a wrong count, a NaN) so that the CLI can print one line and exit with code 2.
#include <cstddef>
#include <filesystem>
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

// A trajectory file whose particle positions hold a NaN or an infinity. The file is well formed:
// it records a simulation that failed, and design.md §4's stability gate ("no NaN/Inf") fails it.
// So the process ends with exit code 1 (kExitGateFailed), as a NaN in a run owval makes does,
// not 2. It is an InputError still: the frame cannot be used, and every judge that turns an
// unreadable input into a failed gate or item (ci quick-test, the checklist) does so unchanged.
class NonFiniteTrajectoryError : public InputError {
 public:
  // what() is "FILE:LINE: MESSAGE: the simulation that wrote this file failed".
  NonFiniteTrajectoryError(const std::string& file, std::size_t line, const std::string& message);
};

// The machine cannot do what was asked, whatever the input: no OSMesa context, no H.264
// encoder, no ffprobe. Exit code 3, so a CI log separates "fix the machine" from "fix the input".
class EnvironmentError : public std::runtime_error {
 public:
  explicit EnvironmentError(const std::string& message);
};

// The user asked to stop (SIGINT during a fit). Its own type so that code between the request
// and the loop that honours it can tell it from a failure; never thrown through a third-party
// library (Ceres sees a failed evaluation and an aborting callback instead).
class Cancelled : public std::runtime_error {
 public:
  Cancelled() : std::runtime_error("cancelled") {}
};

// The simulation itself failed on valid input: a NaN or a diverging particle. One line naming
// the step, the particle and the quantity; the CLI exits with code 1 (kExitGateFailed), not 2.
class SimulationError : public std::runtime_error {
 public:
  explicit SimulationError(const std::string& message);
};

// A filesystem_error that escaped every library check as one line naming its path first:
// "/proc/x: cannot create directories: No such file or directory", not libstdc++'s
// "filesystem error: cannot create directories: ... [/proc/x]".
std::string DescribeFilesystemError(const std::filesystem::filesystem_error& error);

// Exit codes shared by every command (design notes §5).
// kExitInterrupted: a run stopped by SIGINT (128 + the signal, the shell's convention; SIGTERM
// gives 143), after leaving a partial trajectory and a checkpoint.
enum ExitCode : int {
  kExitPass = 0,
  kExitGateFailed = 1,
  kExitBadInput = 2,
  kExitEnvironment = 3,
  kExitInterrupted = 130
};

}  // namespace owval
