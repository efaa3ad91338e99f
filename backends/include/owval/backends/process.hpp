#pragma once
// Runs one shell command as a child process and measures it as a whole: exit status, wall time,
// and CPU time and peak resident memory from wait4's rusage (the child and the descendants it
// waited for).
#include <filesystem>
#include <string>

namespace owval::backends {

struct ProcessOptions {
  std::string command;                      // given to /bin/sh -c
  std::filesystem::path working_directory;  // "" = the current one
  std::filesystem::path stdout_path = "/dev/null";
  std::filesystem::path stderr_path = "/dev/null";
};

struct ProcessResult {
  int exit_code = -1;  // -1 when killed by a signal
  int signal = 0;
  double wall_s = 0;
  double cpu_s = 0;  // user + system time, every thread of the child and its waited descendants
  long peak_rss_kib = 0;
  bool ok() const { return exit_code == 0; }
  std::string Describe() const;  // "exit status 3" | "killed by signal 11"
};

ProcessResult RunShellCommand(const ProcessOptions& options);

// The last `lines` non-empty lines of a log, joined with " | " on one printable line of at most
// `max_chars` (the end kept). "" when the file is empty or missing.
std::string LogTail(const std::filesystem::path& path, std::size_t lines = 5,
                    std::size_t max_chars = 200);

}  // namespace owval::backends
