#include "owval/backends/engine_bench.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>

#include "owval/base/errors.hpp"
#include "owval/engine/profile.hpp"
#include "owval/engine/run.hpp"
#include "owval/engine/solver.hpp"
#include "owval/scenarios/scenario.hpp"

namespace owval::backends {
namespace {

// `steps` steps on `threads` threads, one frame: the physics, not the recording.
nlohmann::json Measure(const engine::SiberneticConfig& config, std::size_t steps, int threads,
                       const std::string& backend) {
  engine::RunOptions o;
  o.backend = backend;
  o.duration_s = double(steps) * o.constants.time_step_s * 1.0000001;
  o.log_step = int(steps) + 1;
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

engine::RunOptions ProfiledRun(const EngineBenchOptions& a) {
  engine::RunOptions o;
  o.backend = a.backend;
  o.threads = a.threads;
  o.duration_s = double(a.steps) * o.constants.time_step_s * 1.0000001;
  o.log_step = a.log_step > 0 ? a.log_step : int(a.steps) + 1;
  if (a.whole_run) {
    o.duration_s = a.whole_run->time_s;
    o.log_step = a.whole_run->log_step;
  }
  if (a.time_s > 0) o.duration_s = a.time_s;
  return o;
}

nlohmann::json Profile(const engine::SiberneticConfig& config, const EngineBenchOptions& a) {
  const engine::RunOptions o = ProfiledRun(a);
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
  if (a.whole_run && a.whole_run->recorded_wall_s > 0) {
    out["sibernetic_wall_s"] = a.whole_run->recorded_wall_s;
    out["sibernetic_wall_includes"] = a.whole_run->recorded_wall_includes;
    out["note"] =
        "in-process steps and frame copies only; the end-to-end figure (process start to last "
        "byte) is owval bench backends owval --scenario " +
        a.whole_run->name;
  }
  return out;
}

}  // namespace

nlohmann::json BenchEngine(const engine::SiberneticConfig& config, const EngineBenchOptions& a) {
  // Without --phases the benchmark times one thread and every thread over --steps: these were
  // accepted and ignored (`bench engine demo1 --threads 1` timed both).
  if (!a.phases) {
    const char* flag = a.threads != 0   ? "--threads"
                       : a.time_s > 0   ? "--time"
                       : a.log_step > 0 ? "--log-step"
                                        : nullptr;
    if (flag)
      throw InputError(std::string("bench engine: ") + flag +
                       " applies to --phases (or --whole-run); without it one thread and every "
                       "thread are timed over --steps");
  }
  nlohmann::json out = {{"benchmark", a.phases ? "engine phases" : "engine"},
                        {"configuration", config.source},
                        {"particles", config.particle_count()},
                        {"moving_particles", config.elastic_count() + config.liquid_count()},
                        {"backend", engine::CanonicalBackend(a.backend)}};
  if (a.phases) {
    out["threads_requested"] = a.threads;  // 0: the engine's rule
    out["profile"] = Profile(config, a);
  } else {
    out["single_thread"] = Measure(config, a.steps, 1, a.backend);
    out["all_threads"] = Measure(config, a.steps, omp_get_max_threads(), a.backend);
  }
  return out;
}

nlohmann::json BenchEngineNamed(const std::string& name,
                                const std::filesystem::path& reference_root,
                                const std::filesystem::path& data_dir, bool whole_run,
                                EngineBenchOptions options) {
  const std::filesystem::path reference = reference_root / name;
  const bool is_reference = std::filesystem::exists(reference / "configuration");
  Scenario scenario;
  if (whole_run) {
    if (!is_reference || !std::filesystem::exists(reference / "meta.json"))
      throw InputError(name, 0,
                       "--whole-run needs a folder of ../shared/reference (configuration and "
                       "meta.json)");
    scenario = ReadScenario(reference);
    options.whole_run = &scenario;
    options.phases = true;
  }
  return BenchEngine(is_reference ? engine::ReadSiberneticConfig(reference / "configuration")
                                  : scenarios::ResolveConfig(name, data_dir),
                     options);
}

nlohmann::json BenchGradient(const engine::SiberneticConfig& config,
                             const engine::GradientOptions& options, double alpha_density) {
  const engine::DifferentiableXpbd model(config, engine::PhysicsConstants{});
  std::vector<double> theta = model.DefaultParameters();
  const auto& names = engine::GradientParameterNames();
  const std::size_t alpha =
      std::size_t(std::find(names.begin(), names.end(), "alpha_density") - names.begin());
  if (alpha_density >= 0) theta[alpha] = alpha_density;  // 0 is a value (a rigid constraint)
  engine::LossTerm loss;
  loss.target = engine::LossTerm::Target::kAllMoving;
  loss.frame_steps = {options.steps};
  std::vector<engine::Vec3d> start;
  for (std::int32_t i : model.moving()) start.push_back(model.initial_positions()[std::size_t(i)]);
  loss.reference = {start};
  const engine::GradientSummary g = model.Gradient(theta, {loss}, options);
  const double steps = double(options.steps);
  return {{"benchmark", "gradient"},
          {"config", config.source},
          {"particles", model.particle_count()},
          {"moving", model.moving().size()},
          {"steps", options.steps},
          {"checkpoint_every", options.checkpoint_every},
          {"alpha_density", theta[alpha]},
          {"forward_s_per_step", g.forward_seconds / steps},
          {"backward_s_per_step", g.backward_seconds / steps},
          {"backward_over_forward", g.backward_seconds / g.forward_seconds},
          {"forward_steps_run", g.forward_steps},
          {"stored_states", g.stored_states},
          {"peak_tape_bytes", g.peak_tape_bytes},
          {"peak_tape_mib", double(g.peak_tape_bytes) / (1024.0 * 1024.0)},
          {"loss", g.loss}};
}

}  // namespace owval::backends
