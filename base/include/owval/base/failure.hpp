#pragma once
// What an application says and exits with when an error reaches it: one line, and the exit code
// of the error's kind (errors.hpp, design notes §5).
#include <exception>
#include <string>

#include "owval/base/errors.hpp"

namespace owval {

struct Failure {
  std::string line;  // "error: MESSAGE" or "environment: MESSAGE"
  int exit_code = kExitBadInput;
};

// InputError: "error: ...", 2. EnvironmentError: "environment: ...", 3. SimulationError:
// "error: ...", 1. filesystem_error: "error: " and its path first (DescribeFilesystemError), 2.
// Any other std::exception: "error: what()", 2. Anything else is rethrown.
Failure DescribeFailure(std::exception_ptr error);

}  // namespace owval
