// owval run: the engine (PCISPH, Sibernetic's scheme, unless --backend says otherwise) on a
// configuration or built-in scenario.
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/progress.hpp"
#include "owval/compare/stability.hpp"
#include "owval/engine/long_run.hpp"
#include "owval/engine/run.hpp"
#include "owval/engine/solver.hpp"
#include "owval/kinematics/midline.hpp"
#include "owval/kinematics/worm_track.hpp"
#include "owval/trajectory/formats.hpp"
#include "owval/trajectory/worm_formats.hpp"
#include "owval/trajectory/writer.hpp"
#include "resolve.hpp"

namespace owval::cli {
namespace {
namespace fs = std::filesystem;

struct RunArgs {
  std::string config;
  double time_s = 0.05;
  int log_step = 1;
  std::string out;
  std::string backend = "pcisph";
  std::string integrator = "euler";
  std::string muscles = "auto";
  std::vector<std::string> set;
  bool apply_physical_parameters = false;
  int threads = 0;
  bool json = false;
  bool no_fields = false;
  bool zarr = false;
  std::size_t checkpoint_every = 0;
  std::string resume;  // output directory of a checkpointed run
  bool stability = false;
};

// The arguments that define a run, saved in its checkpoints: --resume DIR repeats them.
nlohmann::json Invocation(const RunArgs& a) {
  return {{"config", a.config},
          {"time_s", a.time_s},
          {"log_step", a.log_step},
          {"backend", a.backend},
          {"integrator", a.integrator},
          {"muscles", a.muscles},
          {"set", a.set},
          {"apply_physical_parameters", a.apply_physical_parameters},
          {"no_fields", a.no_fields},
          {"zarr", a.zarr},
          {"checkpoint_every", a.checkpoint_every}};
}

// --resume DIR: the checkpointed run's own arguments, its directory as --out. Only --threads,
// --json, --stability and --quiet may change (they change no output byte).
void LoadInvocation(RunArgs* a) {
  const fs::path checkpoint = engine::CheckpointPath(a->resume);
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(engine::ReadCheckpointInvocation(a->resume));
    a->config = j.at("config"), a->time_s = j.at("time_s"), a->log_step = j.at("log_step");
    a->backend = j.at("backend"), a->integrator = j.at("integrator");
    a->muscles = j.at("muscles"), a->set = j.at("set").get<std::vector<std::string>>();
    a->apply_physical_parameters = j.at("apply_physical_parameters");
    a->no_fields = j.at("no_fields"), a->zarr = j.at("zarr");
    a->checkpoint_every = j.at("checkpoint_every");
  } catch (const nlohmann::json::exception& e) {
    throw InputError(checkpoint.string(), 0, std::string("bad run arguments: ") + e.what());
  }
  a->out = a->resume;
}

// SIGINT / SIGTERM only set a flag; the run polls it between steps, checkpoints and leaves a
// partial trajectory (no unwinding from a signal handler).
volatile std::sig_atomic_t g_stop_signal = 0;
extern "C" void OnStopSignal(int signal) { g_stop_signal = signal; }

class StopSignals {
 public:
  StopSignals() {
    g_stop_signal = 0;
    int_ = std::signal(SIGINT, OnStopSignal);
    term_ = std::signal(SIGTERM, OnStopSignal);
  }
  ~StopSignals() {
    std::signal(SIGINT, int_);
    std::signal(SIGTERM, term_);
  }

 private:
  void (*int_)(int);
  void (*term_)(int);
};

// FNV-1a 64 of the configuration file's bytes: identifies the input in WCON provenance.
std::string ConfigurationHash(const std::string& source) {
  std::error_code ec;
  if (!fs::is_regular_file(source, ec)) return "";
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : ReadWholeFile(source)) h = (h ^ c) * 1099511628211ull;
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
  return hex;
}

// A worm run also writes Sibernetic's worm_motion_log.txt and worm.wcon (and the OME-Zarr when
// asked): the formats other OpenWorm tools read.
std::vector<std::string> WriteWormOutputs(const Trajectory& t, const RunArgs& a,
                                          const std::string& source) {
  std::vector<std::string> written;
  const fs::path out = a.out;
  if (a.zarr) {
    WriteOmeZarr(t, out / "trajectory.zarr");
    written.push_back((out / "trajectory.zarr").string());
  }
  if (!kinematics::IsWorm(t)) return written;
  kinematics::WriteWormMotionLog(t, out / "worm_motion_log.txt");
  const nlohmann::json settings = {
      {"configuration", source}, {"configuration_fnv1a64", ConfigurationHash(source)},
      {"backend", a.backend},    {"integrator", a.integrator},
      {"muscles", a.muscles},    {"log_step", a.log_step},
      {"time_s", a.time_s}};
  WormTrack track = kinematics::TrackFromTrajectory(t, settings);
  track.software_version = OWVAL_VERSION;
  WriteWcon(track, out / "worm.wcon");
  written.push_back((out / "worm_motion_log.txt").string());
  written.push_back((out / "worm.wcon").string());
  return written;
}

engine::RunOptions Options(const RunArgs& a) {
  engine::RunOptions options;
  options.duration_s = a.time_s;
  options.log_step = a.log_step;
  options.integrator = a.integrator == "leapfrog" ? engine::Integrator::kLeapfrog
                                                  : engine::Integrator::kSemiImplicitEuler;
  options.apply_physical_parameters = a.apply_physical_parameters;
  options.muscle_signal = a.muscles == "off"     ? engine::MuscleSignal::kOff
                          : a.muscles == "waves" ? engine::MuscleSignal::kSwimmingWaves
                                                 : engine::MuscleSignal::kAuto;
  options.threads = a.threads;
  options.record_fields = !a.no_fields;
  options.backend = engine::CanonicalBackend(a.backend);  // unknown: exit 2 naming the known ones
  options.dump_dir = a.out;
  options.checkpoint_every = a.checkpoint_every;
  for (const std::string& assignment : a.set) SetConstantAssignment(assignment, &options.constants);
  return options;
}

// Worm outputs and OME-Zarr need every frame: read back from the finished trajectory.h5, so
// only such runs hold the trajectory in memory.
std::vector<std::string> WriteWholeTrajectoryOutputs(const Trajectory& header, const RunArgs& a,
                                                     const std::string& source) {
  if (!a.zarr && !kinematics::IsWorm(header)) return {};
  return WriteWormOutputs(ReadHdf5(fs::path(a.out) / "trajectory.h5"), a, source);
}

void Print(const RunArgs& a, const engine::RunSummary& summary, const nlohmann::json& result,
           const compare::StabilityReport* stability) {
  if (a.json) {
    std::cout << result.dump(2) << "\n";
  } else if (!Flags().quiet) {
    if (stability) std::fprintf(stderr, "%s", stability->ToTable().c_str());
    std::fprintf(stderr, "ran steps %zu to %zu in %.2f s (%.0f steps/s), %zu frames -> %s\n",
                 summary.first_step, summary.steps, summary.wall_s, summary.steps_per_s,
                 summary.frames, a.out.c_str());
  }
}

// What the run streams to besides its files: the trajectory's header (for the worm outputs) and,
// with --stability, the gate's monitor.
struct Observers {
  Trajectory header;
  std::unique_ptr<compare::StabilityMonitor> monitor;
};

engine::LongRunOptions Files(const RunArgs& a, Observers* seen) {
  engine::LongRunOptions files;
  files.out = a.out;
  files.resume = !a.resume.empty();
  files.invocation = Invocation(a).dump();
  files.on_begin = [seen, stability = a.stability](const Trajectory& t) {
    seen->header = t;
    if (stability)
      seen->monitor = std::make_unique<compare::StabilityMonitor>(
          t.box, t.type, compare::LongRunStabilityOptions());
  };
  files.on_frame = [seen](const engine::FrameView& f) {
    if (!seen->monitor) return;
    seen->monitor->Observe(f.time_s, f.positions.data(),
                           f.velocities.empty() ? nullptr : f.velocities.data(),
                           f.density.empty() ? nullptr : f.density.data());
  };
  return files;
}

nlohmann::json Result(const std::string& source, const std::string& backend,
                      const engine::RunSummary& summary, const std::vector<std::string>& outputs) {
  return {{"configuration", source},
          {"first_step", summary.first_step},
          {"steps", summary.steps},
          {"frames", summary.frames},
          {"wall_s", summary.wall_s},
          {"steps_per_s", summary.steps_per_s},
          {"backend", backend},
          {"reference_equivalent", summary.reference_equivalent},
          {"muscles_driven", summary.muscles_driven},
          {"interrupted", summary.interrupted},
          {"outputs", outputs}};
}

// Outputs, summary and exit code once the run returned (finished or interrupted).
void Conclude(const RunArgs& a, const engine::SiberneticConfig& config, const std::string& backend,
              const engine::RunSummary& summary, const Observers& seen) {
  for (const std::string& w : summary.warnings)
    std::fprintf(stderr, "owval: warning: %s\n", w.c_str());
  std::vector<std::string> outputs;
  for (const fs::path& output : engine::LongRunOutputs(a.out))
    outputs.push_back((summary.interrupted ? PartialPath(output) : output).string());
  if (!summary.interrupted)
    for (const std::string& path : WriteWholeTrajectoryOutputs(seen.header, a, config.source))
      outputs.push_back(path);
  if (!summary.interrupted && !summary.frame_log.empty()) {
    // An adaptive scheme's time steps, rollbacks and density variation, one entry per frame.
    nlohmann::json log = {{"backend", backend}, {"frames", nlohmann::json::array()}};
    for (const std::string& entry : summary.frame_log)
      log["frames"].push_back(nlohmann::json::parse(entry));
    WriteFileAtomically(fs::path(a.out) / "step_log.json", log.dump(1) + "\n");
    outputs.push_back((fs::path(a.out) / "step_log.json").string());
  }
  nlohmann::json result = Result(config.source, backend, summary, outputs);
  const compare::StabilityReport* stability = seen.monitor ? &seen.monitor->report() : nullptr;
  if (stability) result["stability"] = stability->ToJson();
  Print(a, summary, result, stability);
  if (summary.interrupted) {
    std::fprintf(stderr,
                 "owval: interrupted after step %zu: partial trajectory in %s, checkpoint %s; "
                 "continue with: owval run --resume %s\n",
                 summary.steps, a.out.c_str(), engine::CheckpointPath(a.out).c_str(),
                 a.out.c_str());
    SetExitCode(128 + int(g_stop_signal));  // 130 for SIGINT, 143 for SIGTERM
  } else if (stability && !stability->pass()) {
    SetExitCode(kExitGateFailed);
  }
}

void RunEngine(RunArgs a) {
  if (!a.resume.empty()) LoadInvocation(&a);
  if (a.config.empty() || a.out.empty())
    throw InputError("owval run: give CONFIG and --out DIR, or --resume DIR");
  for (const fs::path& output : engine::LongRunOutputs(a.out)) CheckOutputPath(output);
  const engine::SiberneticConfig config = ResolveConfig(a.config);
  engine::RunOptions options = Options(a);
  Progress progress("run", 0, Flags().quiet);
  options.on_step = [&](std::size_t done, std::size_t total) {
    if (done % 50 == 0 || done == total)
      progress.Update(done, "of " + std::to_string(total) + " steps");
  };
  options.stop_requested = [] { return g_stop_signal != 0; };
  Observers seen;
  engine::RunSummary summary;
  {
    const StopSignals signals;
    summary = engine::RunToFiles(config, options, Files(a, &seen));
  }
  progress.Finish();
  Conclude(a, config, options.backend, summary, seen);
}

void SetUp(CLI::App& app) {
  auto a = std::make_shared<RunArgs>();
  CLI::App* cmd = app.add_subcommand("run", "Phase 2/4: run the reference PCISPH engine");
  cmd->add_option("config", a->config,
                  "Scenario name (owval scenario list) or Sibernetic configuration file");
  cmd->add_option("--time", a->time_s, "Simulated time in seconds (steps = (int)(time/dt))");
  cmd->add_option("--log-step", a->log_step, "Steps between frames")->check(CLI::PositiveNumber);
  cmd->add_option("--out", a->out,
                  "Output directory (position_buffer.txt and trajectory.h5, written as frames "
                  "are produced)");
  std::string backends;
  for (const std::string& name : engine::KnownBackends())
    backends += (backends.empty() ? "" : ", ") + name;
  cmd->add_option("--backend", a->backend,
                  "Time-step scheme: " + backends + " (default pcisph; owval = pcisph)");
  cmd->add_option("--integrator", a->integrator, "euler (Sibernetic's default) or leapfrog")
      ->check(CLI::IsMember({"euler", "leapfrog"}));
  cmd->add_option("--muscles", a->muscles,
                  "Muscle activations: auto (Sibernetic's rule: main_sim's swimming waves when "
                  "the configuration's name contains \"worm\"), waves, or off")
      ->check(CLI::IsMember({"auto", "waves", "off"}));
  cmd->add_option("--set", a->set,
                  "Override a constant, NAME=VALUE (e.g. elasticity_coefficient=3e8); the result "
                  "is then not reference-equivalent");
  cmd->add_flag("--apply-physical-parameters", a->apply_physical_parameters,
                "Apply the configuration's [physical parameters] block (Sibernetic ignores it)");
  cmd->add_option("--threads", a->threads,
                  "OpenMP threads (default: every idle core; one below 4,096 particles)");
  cmd->add_flag("--no-fields", a->no_fields,
                "Record positions only (no velocity, density, pressure): faster");
  cmd->add_flag("--zarr", a->zarr, "Also write trajectory.zarr (OME-Zarr, zarr v2 layout)");
  cmd->add_flag("--json", a->json, "Print a JSON summary");
  cmd->add_option(
      "--checkpoint-every", a->checkpoint_every,
      "Write the solver's state to DIR/checkpoint/checkpoint.bin every N steps (pcisph)");
  cmd->add_option("--resume", a->resume,
                  "Continue the checkpointed run in this output directory with its own "
                  "arguments; the outputs equal an uninterrupted run's byte for byte")
      ->check(CLI::ExistingDirectory);
  cmd->add_flag("--stability", a->stability,
                "Apply the long-run stability gate to every frame as it is produced (NaN, "
                "escapes, kinetic blow-up, density 700-1300 kg/m^3 with at most 1% of liquid "
                "particles outside): exit 1 when it fails");
  cmd->footer(
      "Exit codes: 0 done, 1 simulation failed (NaN: state dump in --out) or --stability gate "
      "failed, 2 bad input, 130 (SIGINT) or 143 (SIGTERM) interrupted (partial trajectory "
      "*.partial.txt/*.partial.h5 and a checkpoint left in --out; continue with --resume).");
  cmd->callback([a] { RunEngine(*a); });
}

const bool registered = RegisterCommand(&SetUp);

}  // namespace
}  // namespace owval::cli
