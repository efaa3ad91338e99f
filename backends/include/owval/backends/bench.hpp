#pragma once
// The same work on each backend, measured as whole processes (owval bench backends): wall time,
// steps/s, particle-steps/s, simulated seconds per wall second, CPU time and peak resident
// memory (wait4's rusage), median and spread (max - min) over N runs, and the ratios of median
// wall times and of median CPU times to the first backend's. CPU time counts every thread's work
// and none of the time the machine gave to other processes: on a shared machine whose speed
// drifts it separates two backends' work where wall time cannot (with the same thread count).
// Built-in backends run the owval executable itself (`owval run ...`). The runs go round by round
// (run 1 of every backend, then run 2, ...), so that a drift in the machine's speed falls on every
// backend alike.
#include <filesystem>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "owval/backends/registry.hpp"
#include "owval/backends/scenario_store.hpp"

namespace owval::backends {

struct BenchOptions {
  Scenario scenario;
  int repeat = 3;
  std::filesystem::path owval_executable;  // the resolved /proc/self/exe
  std::map<std::string, std::string> sets;
  // Built-in backends' `--threads`, the same for every run: 0 = every core of the machine. Left
  // to `owval run`, the count would follow the load average, which the bench's own runs raise:
  // on an idle 2-core machine the first run took two threads and the runs after it one.
  int threads = 0;
  std::function<void(const std::string&)> on_progress;  // may be empty
};

struct BackendTiming {
  std::string backend;
  std::string command;  // as run, {out} a temporary directory
  std::vector<double> wall_s;
  std::vector<double> cpu_s;  // user + system, every thread
  std::vector<long> peak_rss_kib;
  double median_wall_s = 0, spread_wall_s = 0;
  double median_cpu_s = 0;
  double steps_per_s = 0, particle_steps_per_s = 0, simulated_s_per_wall_s = 0;
  double peak_rss_mib = 0;        // maximum over the runs
  double ratio_to_first = 1;      // median wall time / the first backend's
  double cpu_ratio_to_first = 1;  // median CPU time / the first backend's
};

struct BenchReport {
  std::string scenario;
  std::size_t steps = 0, particles = 0;
  double time_s = 0;
  int repeat = 0;
  std::vector<BackendTiming> backends;
  nlohmann::json ToJson() const;
  std::string ToMarkdown() const;
};

// Store backends cannot be timed (InputError). A failing run is an InputError naming the backend
// and the tail of its stderr.
BenchReport BenchBackends(const std::vector<Backend>& backends, const BenchOptions& options);

// The command a backend's timed run executes.
std::string BenchCommand(const Backend& backend, const BenchOptions& options,
                         const std::filesystem::path& out_dir);

}  // namespace owval::backends
