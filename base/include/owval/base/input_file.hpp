#pragma once
// Inputs are regular files. A FIFO blocks open() until a writer appears and a directory or a
// device has no size to check allocations against, so readers call RequireInputFile() before
// they open anything (issue 18 item 14).
#include <filesystem>
#include <string>

namespace owval {

// Throws InputError naming the file when it is missing, or not a regular file (saying what it
// is: a directory, a FIFO, a device, a socket), or one of a set of outputs whose move into place
// was interrupted (OutputGroup's marker in its directory names it). Follows symbolic links.
// The message ends "expected EXPECTED".
void RequireInputFile(const std::filesystem::path& path,
                      const std::string& expected = "a regular file");

// The same for a directory read as input (ci's artifact directory): missing, or what it is instead
// (a file, a FIFO, ...), in one line ending "expected EXPECTED".
void RequireInputDirectory(const std::filesystem::path& path,
                           const std::string& expected = "a directory");

}  // namespace owval
