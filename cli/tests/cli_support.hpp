#pragma once
// Running the owval executable from tests: exit code, stdout and stderr of one command.
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "owval/testing/scratch_directory.hpp"

namespace owval::testing {

struct Result {
  int exit_code = -1;
  std::string out, err;
};

// The running test's own directory, removed when it ends.
inline std::filesystem::path Scratch() { return TestScratch(); }

inline std::string Slurp(const std::filesystem::path& p) {
  std::ifstream in(p);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// Runs a shell command line, capturing its exit code, stdout and stderr.
inline Result RunCaptured(const std::string& command_line) {
  const auto out = Scratch() / "stdout.txt", err = Scratch() / "stderr.txt";
  const std::string command = command_line + " > " + out.string() + " 2> " + err.string();
  const int status = std::system(command.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, Slurp(out), Slurp(err)};
}

// Runs `owval --quiet ARGS` (ARGS as a shell would split them).
inline Result Owval(const std::string& args) {
  // Appended in place: `std::string(OWVAL_EXE) + " --quiet " + args` drew GCC 12's false
  // -Warray-bounds on the inlined copy of the temporary (Release, once gates_test.cpp inlined it).
  std::string command_line = OWVAL_EXE;
  command_line += " --quiet ";
  command_line += args;
  return RunCaptured(command_line);
}

// Sibernetic's reference runs (../shared/reference). CI always has them: there, with
// OWVAL_REQUIRE_REFERENCE=1, a missing file fails the test instead of skipping it.
inline bool ReferenceMissing(const std::filesystem::path& file) {
  if (std::filesystem::exists(file)) return false;
  const char* require = std::getenv("OWVAL_REQUIRE_REFERENCE");
  return !(require && std::string(require) == "1");
}

}  // namespace owval::testing
