#pragma once
// A one-line progress indicator on stderr, shown only when stderr is a terminal and not quiet.
// Long commands (runs, renders, fits, parses of large files) report through it.
#include <chrono>
#include <cstddef>
#include <string>

namespace owval {

class Progress {
 public:
  // total == 0 means unknown. quiet suppresses all output.
  Progress(std::string label, std::size_t total, bool quiet);
  ~Progress();
  // Redraws at most ~10 times a second.
  void Update(std::size_t done, const std::string& detail = "");
  void Finish();

 private:
  std::string label_;
  std::size_t total_;
  bool enabled_;
  bool finished_ = false;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
};

// Global quiet switch set by the CLI's --quiet flag; libraries pass it to Progress.
bool QuietMode();
void SetQuietMode(bool quiet);

}  // namespace owval
