// owval run: the engine (PCISPH, Sibernetic's scheme, unless --backend says otherwise) on a
// configuration or built-in scenario, streamed into an output directory (pipeline/run_directory).
#include <cstdio>
#include <iostream>

#include "command.hpp"
#include "owval/base/command_template.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/progress.hpp"
#include "owval/base/stop_signals.hpp"
#include "owval/engine/long_run.hpp"
#include "owval/engine/solver.hpp"
#include "owval/pipeline/run_directory.hpp"
#include "resolve.hpp"

namespace owval::cli {
namespace {

struct RunArgs {
  pipeline::RunRequest request;
  std::string resume;  // output directory of a checkpointed run
  int threads = 0;
  bool json = false, stability = false;
};

// `path` as one shell word, quoted only when it has to be (the hint is pasted as written).
std::string ShellWord(const std::string& path) {
  const bool plain = !path.empty() && path.find_first_not_of(
                                          "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                                          "0123456789_-./+,:@%") == std::string::npos;
  return plain ? path : ShellQuote(path);
}

void Print(const RunArgs& a, const pipeline::RunRequest& r, const pipeline::RunDirectorySummary& s,
           const std::string& source) {
  for (const std::string& w : s.run.warnings)
    std::fprintf(stderr, "owval: warning: %s\n", w.c_str());
  if (a.json) {
    std::cout << s.ToJson(source).dump(2) << "\n";
  } else if (!Flags().quiet) {
    if (s.stability) std::fprintf(stderr, "%s", s.stability->ToTable().c_str());
    std::fprintf(stderr, "ran steps %zu to %zu in %.2f s (%.0f steps/s), %zu frames -> %s\n",
                 s.run.first_step, s.run.steps, s.run.wall_s, s.run.steps_per_s, s.run.frames,
                 r.out.c_str());
  }
  if (s.run.interrupted) {
    if (s.run.checkpointed)
      std::fprintf(stderr,
                   "owval: interrupted after step %zu: partial trajectory in %s, checkpoint %s; "
                   "continue with: owval run --resume %s\n",
                   s.run.steps, r.out.c_str(), engine::CheckpointPath(r.out).c_str(),
                   ShellWord(r.out).c_str());
    else
      std::fprintf(stderr,
                   "owval: interrupted after step %zu: partial trajectory in %s (backend %s "
                   "cannot checkpoint: no --resume)\n",
                   s.run.steps, r.out.c_str(), s.backend.c_str());
    SetExitCode(128 + StopSignal());  // 130 for SIGINT, 143 for SIGTERM
  } else if (s.stability && !s.stability->pass()) {
    // --quiet silences progress, never the reason for exit 1.
    std::fprintf(stderr, "owval: %s\n", s.stability->FailureLine().c_str());
    SetExitCode(kExitGateFailed);
  }
}

void RunEngine(const RunArgs& a) {
  // --resume DIR: the checkpointed run's own arguments; only --threads, --json, --stability and
  // --quiet may change (they change no output byte).
  const pipeline::RunRequest r =
      a.resume.empty() ? a.request : pipeline::RunRequest::FromCheckpoint(a.resume);
  if (r.config.empty() || r.out.empty())
    throw InputError("owval run: give CONFIG and --out DIR, or --resume DIR");
  const engine::SiberneticConfig config = ResolveConfig(r.config);
  Progress progress("run", 0, Flags().quiet);
  pipeline::RunDirectoryOptions o;
  o.resume = !a.resume.empty(), o.stability = a.stability, o.threads = a.threads;
  o.on_step = [&](std::size_t done, std::size_t total) {
    if (done % 50 == 0 || done == total)
      progress.Update(done, "of " + std::to_string(total) + " steps");
  };
  o.stop_requested = [] { return StopRequested(); };
  pipeline::RunDirectorySummary summary;
  {
    const StopSignals signals;  // checkpoint and leave a partial trajectory
    pipeline::RunIntoDirectory(config, r, o, &summary);
  }
  progress.Finish();
  Print(a, r, summary, config.source);
}

void SetUp(CLI::App& app) {
  auto a = std::make_shared<RunArgs>();
  pipeline::RunRequest& r = a->request;
  CLI::App* cmd = app.add_subcommand("run", "Phase 2/4: run the reference PCISPH engine");
  cmd->add_option("config", r.config,
                  "Scenario name (owval scenario list) or Sibernetic configuration file");
  cmd->add_option("--time", r.time_s, "Simulated time in seconds (steps = (int)(time/dt))");
  cmd->add_option("--log-step", r.log_step, "Steps between frames")->check(Positive());
  cmd->add_option("-o,--out", r.out,
                  "Output directory (position_buffer.txt and trajectory.h5, written as frames "
                  "are produced)");
  std::string backends;
  for (const std::string& name : engine::KnownBackends())
    backends += (backends.empty() ? "" : ", ") + name;
  cmd->add_option("--backend", r.backend,
                  "Time-step scheme: " + backends + " (default pcisph; owval = pcisph)");
  cmd->add_option("--integrator", r.integrator, "euler (Sibernetic's default) or leapfrog")
      ->check(CLI::IsMember({"euler", "leapfrog"}));
  cmd->add_option("--muscles", r.muscles,
                  "Muscle activations: auto (Sibernetic's rule: main_sim's swimming waves when "
                  "the configuration's name contains \"worm\"), waves, or off")
      ->check(CLI::IsMember({"auto", "waves", "off"}));
  cmd->add_option("--set", r.set,
                  "Override a constant, NAME=VALUE (e.g. elasticity_coefficient=3e8); the result "
                  "is then not reference-equivalent");
  cmd->add_flag("--apply-physical-parameters", r.apply_physical_parameters,
                "Apply the configuration's [physical parameters] block (Sibernetic ignores it)");
  cmd->add_option("--threads", a->threads,
                  "OpenMP threads (default: every idle core; one below 4,096 particles)")
      ->check(CLI::Range(0, engine::kMaxThreads));
  cmd->add_flag("--no-fields", r.no_fields,
                "Record positions only (no velocity, density, pressure): faster");
  cmd->add_flag("--zarr", r.zarr, "Also write trajectory.zarr (OME-Zarr, zarr v2 layout)");
  cmd->add_flag("--json", a->json, "Print a JSON summary");
  cmd->add_option(
         "--checkpoint-every", r.checkpoint_every,
         "Write the solver's state to DIR/checkpoint/checkpoint.bin every N steps (pcisph)")
      ->check(Count());
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
