// owval bench engine CONFIG|demo1|one_sprig|<reference folder>: steps per second of the PCISPH
// engine, single thread and all threads; with --phases, where a run's time goes (per phase of the
// step, and the frames' fields), over --steps or, with --whole-run, the reference run's own
// duration and log step (its meta.json, with Sibernetic's recorded wall time). JSON on stdout.
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"
#include "owval/engine/profile.hpp"
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
  bool phases = false, whole_run = false;
  int threads = 0;
  double time_s = 0;
  int log_step = 0;
};

// A folder of ../shared/reference holding the named configuration, or "" (demo1_1s, test_energy,
// worm_alone_0.6s, ...).
std::filesystem::path ReferenceFolder(const std::string& name) {
  const std::filesystem::path dir = std::filesystem::path(OWVAL_SHARED_DIR) / "reference" / name;
  return std::filesystem::exists(dir / "configuration") &&
                 std::filesystem::exists(dir / "meta.json")
             ? dir
             : std::filesystem::path();
}

engine::SiberneticConfig Load(const std::string& name) {
  const std::filesystem::path shared =
      std::filesystem::path(OWVAL_SHARED_DIR) / "reference" / name / "configuration";
  if (std::filesystem::exists(shared)) return engine::ReadSiberneticConfig(shared);
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

nlohmann::json Profile(const engine::SiberneticConfig& config, const BenchEngineArgs& a) {
  engine::RunOptions o;
  o.backend = a.backend;
  o.threads = a.threads;
  o.duration_s = double(a.steps) * o.constants.time_step_s * 1.0000001;
  o.log_step = a.log_step > 0 ? a.log_step : int(a.steps) + 1;
  nlohmann::json reference;
  if (a.whole_run) {
    const std::filesystem::path dir = ReferenceFolder(a.config);
    if (dir.empty())
      throw InputError(a.config, 0,
                       "--whole-run needs a folder of ../shared/reference (configuration and "
                       "meta.json)");
    const std::filesystem::path meta = dir / "meta.json";
    reference = nlohmann::json::parse(ReadWholeFile(meta), nullptr, false);
    // The run's length: timelimit_s, or steps_run (or frames at log step 1) time steps.
    const double steps = reference.value("steps_run", reference.value("frames", 0.0));
    if (reference.contains("timelimit_s") && reference["timelimit_s"].is_number()) {
      o.duration_s = reference["timelimit_s"].get<double>();
    } else if (steps > 0 && reference.value("log_step", 1) == 1) {
      o.duration_s = steps * reference.value("time_step_s", o.constants.time_step_s) * 1.0000001;
    } else {
      throw InputError(meta.string(), 0,
                       "timelimit_s (s), or steps_run with log_step, expected: the run's length");
    }
    o.log_step = std::max(1, reference.value("log_step", 1));
  }
  if (a.time_s > 0) o.duration_s = a.time_s;
  const engine::PhaseProfile p = engine::ProfilePhases(config, o);
  nlohmann::json phases = nlohmann::json::object();
  double step_s = 0;
  for (const auto& t : p.step) {
    phases[t.phase] = t.seconds;
    step_s += t.seconds;
  }
  nlohmann::json out = {{"steps", p.steps},
                        {"frames", p.frames},
                        {"log_step", o.log_step},
                        {"fields", o.record_fields},
                        {"wall_s", p.wall_s},
                        {"ms_per_step", p.steps ? 1e3 * p.wall_s / double(p.steps) : 0.0},
                        {"step_phases_s", phases},
                        {"step_s", step_s},
                        {"muscle_signal_s", p.muscles_s},
                        {"nan_check_s", p.check_s},
                        {"frame_fields_s", p.frame_s}};
  if (reference.contains("wall_s")) {
    out["sibernetic_wall_s"] = reference["wall_s"];
    out["sibernetic_wall_includes"] = reference.value("wall_includes", "");
    out["note"] =
        "in-process steps and frame copies only; the end-to-end figure (process start to last "
        "byte) is owval bench backends owval --scenario " +
        a.config;
  }
  return out;
}

void RunBench(const BenchEngineArgs& a) {
  if (!a.json_out.empty()) CheckOutputPath(a.json_out);
  const engine::SiberneticConfig config = Load(a.config);
  if (a.phases || a.whole_run) {
    nlohmann::json out = {{"benchmark", "engine phases"},
                          {"configuration", config.source},
                          {"particles", config.particle_count()},
                          {"moving_particles", config.elastic_count() + config.liquid_count()},
                          {"backend", engine::CanonicalBackend(a.backend)},
                          // 0: the engine's rule (idle cores; one below 4,096 particles)
                          {"threads_requested", a.threads},
                          {"profile", Profile(config, a)}};
    std::cout << out.dump(2) << "\n";
    if (!a.json_out.empty()) WriteFileAtomically(a.json_out, out.dump(2) + "\n");
    return;
  }
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
  cmd->add_flag("--phases", a->phases,
                "Time each phase of the step and the frames' fields (one run, --threads)");
  cmd->add_flag("--whole-run", a->whole_run,
                "With a reference folder: profile its whole run (meta.json's time and log step)");
  cmd->add_option("--threads", a->threads, "Threads for --phases (default: the engine's rule)");
  cmd->add_option("--time", a->time_s, "Simulated seconds for --phases instead of --steps")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--log-step", a->log_step, "Steps between frames for --phases")
      ->check(CLI::PositiveNumber);
  cmd->callback([a] { RunBench(*a); });
}

const bool registered = RegisterCommand(&SetUp);

}  // namespace
}  // namespace owval::cli
