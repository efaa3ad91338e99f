#pragma once
// A process's own scratch directory: temp_directory_path()/PREFIX-XXXXXX (TMPDIR honoured), made
// by mkdtemp so that two processes never share one, and removed with its contents when destroyed,
// whether the work succeeded or threw, and when SIGINT or SIGTERM ends the process
// (RemoveTemporariesOnSignal). `owval bench` and `owval checklist --scenario` left theirs in /tmp
// after a failure or a Ctrl-C. The tests' scratch directories are these too
// (owval/testing/scratch_directory.hpp), kept on request for looking at a failing test's files.
#include <filesystem>
#include <string>

namespace owval {

class TemporaryDirectory {
 public:
  // What becomes of the directory when it is destroyed or a signal ends the process.
  enum class OnExit { kRemove, kKeep };
  // EnvironmentError when the directory cannot be made.
  explicit TemporaryDirectory(const std::string& prefix, OnExit on_exit = OnExit::kRemove);
  ~TemporaryDirectory();
  TemporaryDirectory(const TemporaryDirectory&) = delete;
  TemporaryDirectory& operator=(const TemporaryDirectory&) = delete;

  const std::filesystem::path& path() const { return path_; }
  bool kept() const { return on_exit_ == OnExit::kKeep; }

 private:
  std::filesystem::path path_;
  OnExit on_exit_;
  int signal_slot_ = -1;
};

}  // namespace owval
