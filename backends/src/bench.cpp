#include "owval/backends/bench.hpp"

#include <unistd.h>
#include <algorithm>
#include <cmath>

#include <cstdio>
#include <thread>

#include "owval/backends/process.hpp"
#include "owval/backends/runner.hpp"
#include "owval/base/command_template.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/format.hpp"
#include "owval/base/temporary_directory.hpp"
#include "owval/engine/config.hpp"

namespace owval::backends {
namespace fs = std::filesystem;

namespace {

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Run `run` (0-based) of backend b, its wall time and peak memory added to t.
void TimeOneRun(const Backend& b, const BenchOptions& o, int run, BackendTiming* t) {
  // Removed however the run ends: success, a failed command, an exception, SIGINT or SIGTERM.
  const TemporaryDirectory scratch("owval-bench-run" + std::to_string(run + 1));
  const fs::path& dir = scratch.path();
  fs::create_directories(dir / "out");
  ProcessOptions p;
  p.command = BenchCommand(b, o, dir / "out");
  p.working_directory = b.working_directory;
  p.stderr_path = dir / "stderr.txt";
  if (run == 0) t->command = p.command;  // later runs differ only in {out}
  if (o.on_progress)
    o.on_progress(b.name + ": run " + std::to_string(run + 1) + " of " + std::to_string(o.repeat));
  const ProcessResult r = RunShellCommand(p);
  if (!r.ok()) {
    const std::string tail = LogTail(p.stderr_path, 5, 150);
    throw InputError("backend " + b.name + ": command failed, " + r.Describe() +
                     (tail.empty() ? "" : " (stderr: " + tail + ")"));
  }
  t->wall_s.push_back(r.wall_s);
  t->cpu_s.push_back(r.cpu_s);
  t->peak_rss_kib.push_back(r.peak_rss_kib);
}

void Summarise(const BenchOptions& o, std::size_t steps, std::size_t particles, BackendTiming* t) {
  t->median_wall_s = Median(t->wall_s);
  t->spread_wall_s = *std::max_element(t->wall_s.begin(), t->wall_s.end()) -
                     *std::min_element(t->wall_s.begin(), t->wall_s.end());
  t->median_cpu_s = Median(t->cpu_s);
  t->steps_per_s = steps / t->median_wall_s;
  t->particle_steps_per_s = t->steps_per_s * particles;
  t->simulated_s_per_wall_s = o.scenario.time_s / t->median_wall_s;
  t->peak_rss_mib = *std::max_element(t->peak_rss_kib.begin(), t->peak_rss_kib.end()) / 1024.0;
}

int ThreadsOf(const BenchOptions& o) {
  return o.threads > 0 ? o.threads : std::max(1, int(std::thread::hardware_concurrency()));
}

}  // namespace

std::string BenchCommand(const Backend& b, const BenchOptions& o, const fs::path& out_dir) {
  if (b.kind == BackendKind::kStore)
    throw InputError("backend " + b.name + ": a store of recorded runs cannot be timed");
  if (b.kind == BackendKind::kBuiltin)
    return ShellQuote(o.owval_executable.string()) + " --quiet run " +
           ShellQuote(fs::absolute(o.scenario.configuration).string()) + " --time " +
           FormatNumber(o.scenario.time_s, 17) + " --log-step " +
           std::to_string(o.scenario.log_step) + " --out " + ShellQuote(out_dir.string()) +
           " --backend " + b.engine_backend + " --threads " + std::to_string(ThreadsOf(o));
  RunRequest request;
  request.scenario = o.scenario;
  request.sets = o.sets;
  return ResolvedCommand(b, request, out_dir);
}

BenchReport BenchBackends(const std::vector<Backend>& backends, const BenchOptions& o) {
  if (o.repeat < 1) throw InputError("--repeat: expected >= 1");
  if (o.scenario.configuration.empty())
    throw InputError(o.scenario.directory.string(), 0, "no configuration file to run");
  const engine::SiberneticConfig config = engine::ReadSiberneticConfig(o.scenario.configuration);
  BenchReport report;
  report.scenario = o.scenario.name;
  report.time_s = o.scenario.time_s;
  report.repeat = o.repeat;
  report.steps = static_cast<std::size_t>(static_cast<float>(o.scenario.time_s) /
                                          static_cast<float>(o.scenario.time_step_s));
  report.particles = config.particle_count();
  report.backends.resize(backends.size());
  for (std::size_t b = 0; b < backends.size(); ++b) {
    BenchCommand(backends[b], o, "/tmp");  // refuses stores before any work
    report.backends[b].backend = backends[b].name;
  }
  // Round by round, each backend once per round: a machine whose speed drifts (other work on
  // it) then slows every backend alike, where timing one backend's runs after another's would
  // put the drift into their ratio.
  for (int run = 0; run < o.repeat; ++run)
    for (std::size_t b = 0; b < backends.size(); ++b)
      TimeOneRun(backends[b], o, run, &report.backends[b]);
  for (BackendTiming& t : report.backends) Summarise(o, report.steps, report.particles, &t);
  for (BackendTiming& t : report.backends) {
    t.ratio_to_first = t.median_wall_s / report.backends.front().median_wall_s;
    const double first_cpu_s = report.backends.front().median_cpu_s;  // 0 for a trivial command
    t.cpu_ratio_to_first = first_cpu_s > 0 ? t.median_cpu_s / first_cpu_s : std::nan("");
  }
  return report;
}

nlohmann::json BenchReport::ToJson() const {
  nlohmann::json j = {{"scenario", scenario},
                      {"steps", steps},
                      {"particles", particles},
                      {"time_s", time_s},
                      {"repeat", repeat}};
  j["backends"] = nlohmann::json::array();
  for (const BackendTiming& t : backends)
    j["backends"].push_back({{"backend", t.backend},
                             {"command", t.command},
                             {"wall_s", t.wall_s},
                             {"peak_rss_kib", t.peak_rss_kib},
                             {"median_wall_s", t.median_wall_s},
                             {"spread_wall_s", t.spread_wall_s},
                             {"steps_per_s", t.steps_per_s},
                             {"particle_steps_per_s", t.particle_steps_per_s},
                             {"simulated_s_per_wall_s", t.simulated_s_per_wall_s},
                             {"peak_rss_mib", t.peak_rss_mib},
                             {"ratio_to_first", t.ratio_to_first},
                             {"cpu_s", t.cpu_s},
                             {"median_cpu_s", t.median_cpu_s},
                             {"cpu_ratio_to_first", t.cpu_ratio_to_first}});
  return j;
}

std::string BenchReport::ToMarkdown() const {
  char line[512];
  std::snprintf(line, sizeof line,
                "Scenario `%s`: %zu steps, %zu particles, %.4g simulated s, %d runs each.\n\n",
                scenario.c_str(), steps, particles, time_s, repeat);
  std::string m = line;
  m += "| backend | median wall s | spread s | steps/s | particle-steps/s | sim s / wall s | "
       "peak RSS MiB | wall / first | median CPU s | CPU / first |\n"
       "|---|---|---|---|---|---|---|---|---|---|\n";
  for (const BackendTiming& t : backends) {
    std::snprintf(line, sizeof line,
                  "| %s | %.3f | %.3f | %.1f | %.3g | %.4f | %.1f | %.2f | %.3f | %.2f |\n",
                  t.backend.c_str(), t.median_wall_s, t.spread_wall_s, t.steps_per_s,
                  t.particle_steps_per_s, t.simulated_s_per_wall_s, t.peak_rss_mib,
                  t.ratio_to_first, t.median_cpu_s, t.cpu_ratio_to_first);
    m += line;
  }
  return m;
}

}  // namespace owval::backends
