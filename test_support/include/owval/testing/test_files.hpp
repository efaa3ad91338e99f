#pragma once
// What many folders' tests wrote each for themselves: the bundled one_sprig run, a file in the
// test's scratch directory, a file's bytes, and the message of the bad input a call refuses.
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "owval/base/errors.hpp"
#include "owval/testing/scratch_directory.hpp"

namespace owval::testing {

#ifdef OWVAL_SOURCE_DIR
// Sibernetic's one_sprig run as bundled in reference_trajectories/ (always present, unlike
// ../shared/reference).
inline const std::filesystem::path kBundledOneSprig =
    std::filesystem::path(OWVAL_SOURCE_DIR) /
    "reference_trajectories/one_sprig/position_buffer.txt";
#endif

#ifdef OWVAL_SHARED_DIR
// ../shared: Sibernetic's own runs (reference/) and the fact sheets, when present.
inline const std::filesystem::path kSharedDir = OWVAL_SHARED_DIR;
#endif

// NAME in the running test's scratch directory (not created).
inline std::filesystem::path ScratchFile(const std::string& name) { return TestScratch() / name; }

// The whole file, byte for byte ("" when it cannot be read).
inline std::string FileBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// The message of the InputError `action` throws, or "no error": what bad-input tests compare.
template <class Action>
std::string InputErrorOf(Action&& action) {
  try {
    action();
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace owval::testing
