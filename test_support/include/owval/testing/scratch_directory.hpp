#pragma once
// Where tests put their files: a directory of their own under temp_directory_path() (TMPDIR
// honoured), removed with its contents when the test ends, whether it passed or failed, and when
// SIGINT or SIGTERM ends a test program that called RemoveTemporariesOnSignal. Earlier
// tests wrote to fixed names or per-process names they never removed: /tmp held 12,511 owval_*
// entries (about 40 GB) after a few days of runs.
//
// OWVAL_KEEP_TEST_FILES=1 keeps every scratch directory and prints its path, for looking at a
// failing test's files.
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>

#include "owval/base/temporary_directory.hpp"

namespace owval::testing {

inline bool KeepTestFiles() {
  const char* keep = std::getenv("OWVAL_KEEP_TEST_FILES");
  return keep && std::string(keep) == "1";
}

// A TemporaryDirectory named owval_[LABEL_]PID-XXXXXX (two tests, two build trees or two runs of
// one test, ctest -j2 or --repeat, never share one), kept and named with OWVAL_KEEP_TEST_FILES=1.
// Short on purpose: owval shortens a path of more than 80 characters in its messages, and tests
// compare those messages.
class ScratchDirectory {
 public:
  // OWNER (a test's name) is printed with the path when the directory is kept.
  explicit ScratchDirectory(const std::string& label = "", std::string owner = "")
      : directory_(Prefix(label), KeepTestFiles() ? TemporaryDirectory::OnExit::kKeep
                                                  : TemporaryDirectory::OnExit::kRemove),
        owner_(std::move(owner)) {}
  ~ScratchDirectory() {
    if (directory_.kept())
      std::fprintf(stderr, "OWVAL_KEEP_TEST_FILES=1: kept %s%s%s\n", path().c_str(),
                   owner_.empty() ? "" : " for ", owner_.c_str());
  }
  ScratchDirectory(const ScratchDirectory&) = delete;
  ScratchDirectory& operator=(const ScratchDirectory&) = delete;

  const std::filesystem::path& path() const { return directory_.path(); }
  std::filesystem::path operator/(const std::filesystem::path& name) const { return path() / name; }

 private:
  static std::string Prefix(std::string label) {
    std::replace_if(
        label.begin(), label.end(), [](char c) { return !std::isalnum((unsigned char)c); }, '_');
    return "owval_" + (label.empty() ? "" : label + "_") + std::to_string(::getpid());
  }

  TemporaryDirectory directory_;
  std::string owner_;
};

// How many entries DIR holds (what a test left behind, what a run wrote).
inline std::size_t CountEntries(const std::filesystem::path& dir) {
  std::size_t n = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir)) ++n;
  return n;
}

namespace detail {
// The running test's directory (made on first use) and the test program's (for data a suite
// shares between its tests); test_main.cpp's listener ends each.
inline std::unique_ptr<ScratchDirectory>& TestScratchSlot() {
  static std::unique_ptr<ScratchDirectory> slot;
  return slot;
}
inline std::unique_ptr<ScratchDirectory>& ProgramScratchSlot() {
  static std::unique_ptr<ScratchDirectory> slot;
  return slot;
}
// Set by the listener: the running test's Suite.Name, empty between tests.
inline std::string& RunningTestName() {
  static std::string name;
  return name;
}
}  // namespace detail

// The program's scratch directory, for files a suite's tests share (a cached run, a function-local
// static): removed when the test program ends.
inline std::filesystem::path ProgramScratch() {
  auto& slot = detail::ProgramScratchSlot();
  if (!slot) slot = std::make_unique<ScratchDirectory>("", "the test program");
  return slot->path();
}

// The running test's scratch directory: removed when the test ends, pass or fail, even when an
// ASSERT returned early or the test threw. Outside a test (SetUpTestSuite, static data) it is
// ProgramScratch().
inline std::filesystem::path TestScratch() {
  if (detail::RunningTestName().empty()) return ProgramScratch();
  auto& slot = detail::TestScratchSlot();
  if (!slot) slot = std::make_unique<ScratchDirectory>("", detail::RunningTestName());
  return slot->path();
}

// A subdirectory NAME of TestScratch(), made empty.
inline std::filesystem::path TestScratch(const std::string& name) {
  const std::filesystem::path dir = TestScratch() / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace owval::testing
