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

// Exit codes shared by every command (design notes §5).
enum ExitCode : int { kExitPass = 0, kExitGateFailed = 1, kExitBadInput = 2 };

}  // namespace owval
