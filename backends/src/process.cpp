#include "owval/backends/process.hpp"

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace owval::backends {

std::string ProcessResult::Describe() const {
  return signal ? "killed by signal " + std::to_string(signal)
                : "exit status " + std::to_string(exit_code);
}

namespace {

// In the child: redirect, change directory, exec the shell. Never returns.
[[noreturn]] void ExecChild(const ProcessOptions& o) {
  const int out = ::open(o.stdout_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  const int err = ::open(o.stderr_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (out >= 0) ::dup2(out, 1);
  if (err >= 0) ::dup2(err, 2);
  if (!o.working_directory.empty() && ::chdir(o.working_directory.c_str()) != 0) {
    std::fprintf(stderr, "cannot enter working directory %s\n", o.working_directory.c_str());
    ::_exit(126);
  }
  ::execl("/bin/sh", "sh", "-c", o.command.c_str(), static_cast<char*>(nullptr));
  ::_exit(127);
}

}  // namespace

ProcessResult RunShellCommand(const ProcessOptions& options) {
  std::fflush(nullptr);
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = ::fork();
  if (pid < 0) throw std::runtime_error("fork failed");
  if (pid == 0) ExecChild(options);
  int status = 0;
  rusage usage{};
  while (::wait4(pid, &status, 0, &usage) < 0)
    if (errno != EINTR) throw std::runtime_error("wait4 failed");
  ProcessResult r;
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.cpu_s = double(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
            double(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec) * 1e-6;
  r.peak_rss_kib = usage.ru_maxrss;
  if (WIFEXITED(status)) r.exit_code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) r.signal = WTERMSIG(status);
  return r;
}

std::string LogTail(const std::filesystem::path& path, std::size_t lines, std::size_t max_chars) {
  std::ifstream in(path);
  std::vector<std::string> kept;
  for (std::string line; std::getline(in, line);) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    kept.push_back(line);
    if (kept.size() > lines) kept.erase(kept.begin());
  }
  std::string tail;
  for (const std::string& line : kept) {
    if (!tail.empty()) tail += " | ";
    for (char c : line) tail += (c >= 32 && c < 127) ? c : (c == '\t' ? ' ' : '?');
  }
  if (tail.size() > max_chars) tail = "..." + tail.substr(tail.size() - (max_chars - 3));
  return tail;
}

}  // namespace owval::backends
