// owval run: the engine (PCISPH, Sibernetic's scheme, unless --backend says otherwise) on a
// configuration or built-in scenario.
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/progress.hpp"
#include "owval/engine/run.hpp"
#include "owval/engine/solver.hpp"
#include "owval/kinematics/midline.hpp"
#include "owval/kinematics/worm_track.hpp"
#include "owval/trajectory/formats.hpp"
#include "owval/trajectory/worm_formats.hpp"
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

void RunEngine(const RunArgs& a) {
  const engine::SiberneticConfig config = ResolveConfig(a.config);
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
  for (const std::string& assignment : a.set) SetConstantAssignment(assignment, &options.constants);
  Progress progress("run", 0, Flags().quiet);
  options.on_step = [&](std::size_t done, std::size_t total) {
    if (done % 50 == 0 || done == total)
      progress.Update(done, "of " + std::to_string(total) + " steps");
  };
  engine::RunSummary summary;
  const Trajectory t = engine::Run(config, options, &summary);
  progress.Finish();
  for (const std::string& w : summary.warnings)
    std::fprintf(stderr, "owval: warning: %s\n", w.c_str());
  const fs::path out = a.out;
  WriteSiberneticText(t, out / "position_buffer.txt", TextLayout::kOpenCL);
  WriteHdf5(t, out / "trajectory.h5");
  std::vector<std::string> outputs = {(out / "position_buffer.txt").string(),
                                      (out / "trajectory.h5").string()};
  for (const std::string& path : WriteWormOutputs(t, a, config.source)) outputs.push_back(path);
  if (!summary.frame_log.empty()) {
    // An adaptive scheme's time steps, rollbacks and density variation, one entry per frame.
    nlohmann::json log = {{"backend", options.backend}, {"frames", nlohmann::json::array()}};
    for (const std::string& entry : summary.frame_log)
      log["frames"].push_back(nlohmann::json::parse(entry));
    WriteFileAtomically(out / "step_log.json", log.dump(1) + "\n");
    outputs.push_back((out / "step_log.json").string());
  }
  nlohmann::json result = {{"configuration", config.source},
                           {"steps", summary.steps},
                           {"frames", summary.frames},
                           {"wall_s", summary.wall_s},
                           {"steps_per_s", summary.steps_per_s},
                           {"backend", options.backend},
                           {"reference_equivalent", summary.reference_equivalent},
                           {"muscles_driven", summary.muscles_driven},
                           {"outputs", outputs}};
  if (a.json) {
    std::cout << result.dump(2) << "\n";
  } else if (!Flags().quiet) {
    std::fprintf(stderr, "ran %zu steps in %.2f s (%.0f steps/s), %zu frames -> %s\n",
                 summary.steps, summary.wall_s, summary.steps_per_s, summary.frames, out.c_str());
  }
}

void SetUp(CLI::App& app) {
  auto a = std::make_shared<RunArgs>();
  CLI::App* cmd = app.add_subcommand("run", "Phase 2/4: run the reference PCISPH engine");
  cmd->add_option("config", a->config,
                  "Scenario name (owval scenario list) or Sibernetic configuration file")
      ->required();
  cmd->add_option("--time", a->time_s, "Simulated time in seconds (steps = (int)(time/dt))");
  cmd->add_option("--log-step", a->log_step, "Steps between frames")->check(CLI::PositiveNumber);
  cmd->add_option("--out", a->out, "Output directory (position_buffer.txt and trajectory.h5)")
      ->required();
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
  cmd->add_option("--threads", a->threads, "OpenMP threads (default: all)");
  cmd->add_flag("--no-fields", a->no_fields,
                "Record positions only (no velocity, density, pressure): faster");
  cmd->add_flag("--zarr", a->zarr, "Also write trajectory.zarr (OME-Zarr, zarr v2 layout)");
  cmd->add_flag("--json", a->json, "Print a JSON summary");
  cmd->callback([a] { RunEngine(*a); });
}

const bool registered = RegisterCommand(&SetUp);

}  // namespace
}  // namespace owval::cli
