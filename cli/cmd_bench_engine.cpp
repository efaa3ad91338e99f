// owval bench engine CONFIG|demo1|one_sprig: steps per second of the PCISPH engine, single thread
// and all threads. JSON on stdout.
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "owval/base/atomic_output.hpp"
#include "owval/engine/run.hpp"
#include "owval/engine/solver.hpp"
#include "resolve.hpp"

namespace owval::cli {
namespace {

struct BenchEngineArgs {
  std::string config = "demo1";
  std::size_t steps = 1000;
  std::string json_out;
  std::string backend = "pcisph";
};

engine::SiberneticConfig Load(const std::string& name) {
  const std::filesystem::path shared =
      std::filesystem::path(OWVAL_SHARED_DIR) / "reference" / name / "configuration";
  if ((name == "demo1" || name == "one_sprig") && std::filesystem::exists(shared))
    return engine::ReadSiberneticConfig(shared);
  return ResolveConfig(name);
}

nlohmann::json Measure(const engine::SiberneticConfig& config, std::size_t steps, int threads,
                       const std::string& backend) {
  engine::RunOptions o;
  o.backend = backend;
  o.constants = engine::PhysicsConstants{};
  o.duration_s = double(steps) * o.constants.time_step_s * 1.0000001;
  o.log_step = int(steps) + 1;  // one frame: measure the physics, not the recording
  o.record_fields = false;
  o.threads = threads;
  std::vector<double> step_ms;
  auto last = std::chrono::steady_clock::now();
  o.on_step = [&](std::size_t, std::size_t) {
    const auto now = std::chrono::steady_clock::now();
    step_ms.push_back(std::chrono::duration<double, std::milli>(now - last).count());
    last = now;
  };
  engine::RunSummary summary;
  engine::Run(config, o, &summary);
  std::sort(step_ms.begin(), step_ms.end());
  const double median = step_ms.empty() ? 0 : step_ms[step_ms.size() / 2];
  const double moving = double(config.elastic_count() + config.liquid_count());
  return {{"threads", threads},
          {"steps", summary.steps},
          {"wall_s", summary.wall_s},
          {"steps_per_s", summary.steps_per_s},
          {"median_ms_per_step", median},
          {"particle_steps_per_s", summary.steps_per_s * double(config.particle_count())},
          {"moving_particle_steps_per_s", summary.steps_per_s * moving}};
}

void RunBench(const BenchEngineArgs& a) {
  const engine::SiberneticConfig config = Load(a.config);
  nlohmann::json out = {
      {"benchmark", "engine"},
      {"configuration", config.source},
      {"particles", config.particle_count()},
      {"moving_particles", config.elastic_count() + config.liquid_count()},
      {"backend", engine::CanonicalBackend(a.backend)},
      {"single_thread", Measure(config, a.steps, 1, a.backend)},
      {"all_threads", Measure(config, a.steps, omp_get_max_threads(), a.backend)}};
  std::cout << out.dump(2) << "\n";
  if (!a.json_out.empty()) WriteFileAtomically(a.json_out, out.dump(2) + "\n");
}

void SetUp(CLI::App& app) {
  auto a = std::make_shared<BenchEngineArgs>();
  CLI::App* cmd = Bench(app).add_subcommand(
      "engine", "PCISPH engine speed (steps/s), one thread and all threads");
  cmd->add_option("config", a->config,
                  "demo1, one_sprig (Sibernetic's files in ../shared), a scenario or a file");
  cmd->add_option("--steps", a->steps, "Steps to time");
  cmd->add_option("--json-out", a->json_out, "Also write the JSON result here");
  cmd->add_option("--backend", a->backend, "Solver to time (pcisph, xpbd; default pcisph)");
  cmd->callback([a] { RunBench(*a); });
}

const bool registered = RegisterCommand(&SetUp);

}  // namespace
}  // namespace owval::cli
