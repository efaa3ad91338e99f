#pragma once
// A process's own scratch directory: temp_directory_path()/PREFIX-XXXXXX (TMPDIR honoured), made
// by mkdtemp so that two processes never share one, and removed with its contents when destroyed,
// whether the work succeeded or threw, and when SIGINT or SIGTERM ends the process
// (RemoveTemporariesOnSignal). `owval bench` and `owval checklist --scenario` left theirs in /tmp
// after a failure or a Ctrl-C.
#include <filesystem>
#include <string>

namespace owval {

class TemporaryDirectory {
 public:
  // EnvironmentError when the directory cannot be made.
  explicit TemporaryDirectory(const std::string& prefix);
  ~TemporaryDirectory();
  TemporaryDirectory(const TemporaryDirectory&) = delete;
  TemporaryDirectory& operator=(const TemporaryDirectory&) = delete;

  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  int signal_slot_ = -1;
};

}  // namespace owval
