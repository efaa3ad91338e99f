#pragma once
// How the trajectory tests read bad files: without progress lines, keeping the message a reader
// refuses the file with (what the tests compare).
#include <filesystem>
#include <string>

#include "owval/testing/test_files.hpp"
#include "owval/trajectory/formats.hpp"

namespace owval::testing {

inline TextReadOptions QuietReading() {
  TextReadOptions options;
  options.quiet = true;
  return options;
}

// ReadTrajectory's refusal of `path`, or "no error".
inline std::string ReadError(const std::filesystem::path& path) {
  return InputErrorOf([&] { ReadTrajectory(path); });
}

}  // namespace owval::testing
