#pragma once
// Running the owval executable as a child process for the long-run tests: signals, peak
// resident memory (wait4's rusage) and dataset-by-dataset comparison of two outputs.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "owval/testing/scratch_directory.hpp"
#include "owval/trajectory/formats.hpp"

extern char** environ;

namespace owval::testing {
namespace fs = std::filesystem;

inline const fs::path kOwval = fs::path(OWVAL_BINARY_DIR) / "owval";
inline const fs::path kDemo1 = fs::path(OWVAL_SHARED_DIR) / "reference/demo1/configuration";

// DIR for a run's output, not yet made, in the running test's scratch directory.
inline fs::path ScratchDir(const std::string& name) {
  const fs::path dir = TestScratch() / name;
  fs::remove_all(dir);
  return dir;
}

// Starts `owval --quiet ARGS...` with stdout and stderr to DIR/../NAME.log; returns its pid.
inline pid_t Start(const std::vector<std::string>& args, const fs::path& log) {
  std::vector<std::string> all = {kOwval.string(), "--quiet"};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  pid_t pid = -1;
  const int error = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (error != 0) ADD_FAILURE() << "cannot start " << argv[0];
  return pid;
}

struct Finished {
  int exit_code = -1;      // -1 when killed by a signal
  int signal = 0;          // the signal that ended it, or 0
  double peak_rss_mb = 0;  // ru_maxrss of the child
  double wall_s = 0;
};

inline Finished Wait(pid_t pid, std::chrono::steady_clock::time_point start) {
  Finished f;
  int status = 0;
  rusage usage{};
  if (::wait4(pid, &status, 0, &usage) != pid) return f;
  f.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  f.signal = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
  f.peak_rss_mb = double(usage.ru_maxrss) / 1024.0;
  f.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return f;
}

inline Finished RunOwval(const std::vector<std::string>& args, const fs::path& log) {
  const auto start = std::chrono::steady_clock::now();
  return Wait(Start(args, log), start);
}

inline std::string Bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Polls until `ready` or the timeout; false on timeout.
template <typename Predicate>
bool WaitFor(Predicate ready, double timeout_s) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (!ready()) {
    if (std::chrono::steady_clock::now() > until) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return true;
}

template <typename T>
bool SameBits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

// Every dataset of two owval HDF5 trajectories equal bit for bit.
inline void ExpectSameHdf5Datasets(const fs::path& a, const fs::path& b) {
  const Trajectory x = ReadHdf5(a), y = ReadHdf5(b);
  EXPECT_TRUE(SameBits(x.type, y.type));
  EXPECT_TRUE(SameBits(x.time_s, y.time_s));
  EXPECT_TRUE(SameBits(x.positions, y.positions));
  EXPECT_TRUE(SameBits(x.velocities, y.velocities));
  EXPECT_TRUE(SameBits(x.density, y.density));
  EXPECT_TRUE(SameBits(x.pressure, y.pressure));
  EXPECT_EQ(x.provenance, y.provenance);
  EXPECT_EQ(x.frame_count(), y.frame_count());
}

}  // namespace owval::testing
