#pragma once
// Running the owval executable from tests: exit code, stdout and stderr of one command.
#include <fcntl.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "owval/testing/scratch_directory.hpp"
#include "owval/testing/test_files.hpp"

namespace owval::testing {

struct Result {
  int exit_code = -1;
  std::string out, err;
};

// The bundled one_sprig run (kBundledOneSprig) as a command-line argument.
inline const std::string kOneSprig = kBundledOneSprig.string();

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

// A ready pipeline directory (one_sprig, 20 video frames, about 12 s to make), made once per
// build of owval and shared: ctest runs each test in its own process, in parallel, so it is
// keyed by the executable's time stamp and made under a file lock by whichever test needs it
// first. It lives in the build tree beside the executable that made it, and replaces the one an
// earlier build made. Tests copy it before they change anything in it.
inline std::filesystem::path ReadyPipelineDirectory() {
  namespace fs = std::filesystem;
  const auto stamp = fs::last_write_time(OWVAL_EXE).time_since_epoch().count();
  const fs::path cache = fs::path(OWVAL_EXE).parent_path() / "test_cache";
  const fs::path d = cache / ("checklist_ready_" + std::to_string(stamp));
  fs::create_directories(cache);
  const int lock = ::open((cache / "checklist_ready.lock").c_str(), O_CREAT | O_RDWR, 0600);
  ::flock(lock, LOCK_EX);
  if (!fs::exists(d / "complete")) {
    for (const fs::directory_entry& e : fs::directory_iterator(cache))
      if (e.path().filename().string().rfind("checklist_ready_", 0) == 0) fs::remove_all(e);
    const Result r = Owval("pipeline one_sprig -o " + d.string() + " --max-video-frames 20");
    if (r.exit_code == 0) std::ofstream(d / "complete") << "made by the first test to need it\n";
  }
  ::flock(lock, LOCK_UN);
  ::close(lock);
  return d;
}

// A report's gate of that name (report["gates"]: the checklist's and compare's JSON), or null.
inline const nlohmann::json* GateNamed(const nlohmann::json& report, const std::string& name) {
  for (const nlohmann::json& g : report["gates"])
    if (g["name"] == name) return &g;
  return nullptr;
}

}  // namespace owval::testing
