// owval run: the engine (PCISPH, Sibernetic's scheme, unless --backend says otherwise) on a
// configuration or built-in scenario, streamed into an output directory (pipeline/run_directory).
#include <cstddef>
#include <cstdio>
#include <vector>

#include "command.hpp"
#include "owval/base/stop_signals.hpp"
#include "owval/compare/stability.hpp"
#include "owval/engine/solver.hpp"
#include "owval/pipeline/run_directory.hpp"
#include "run_flags.hpp"

namespace owval::cli {
namespace {

struct RunArgs {
  pipeline::RunRequest request;
  pipeline::RunDirectoryOptions options;
  std::string resume;  // output directory of a checkpointed run
  bool json = false;
};

void RunEngine(RunArgs& a) {
  // --resume DIR: the checkpointed run's own arguments; only --threads, --json, --stability and
  // --quiet may change (they change no output byte).
  a.options.resume = !a.resume.empty();
  a.options.stop_requested = [] { return StopRequested(); };
  pipeline::RunDirectorySummary s;
  {
    const StopSignals signals;  // checkpoint and leave a partial trajectory
    s = pipeline::RunNamedIntoDirectory(
        a.resume.empty() ? a.request : pipeline::RunRequest::FromCheckpoint(a.resume), a.options,
        DataDir(), QuietMode());
  }
  for (const std::string& w : s.run.warnings)
    std::fprintf(stderr, "owval: warning: %s\n", w.c_str());
  if (a.json)
    std::cout << s.ToJson(s.configuration).dump(2) << "\n";
  else if (!QuietMode())
    std::cerr << s.ToText();
  // --quiet silences progress, never the reason for a non-zero exit.
  if (const std::string why = s.FailureLine(); !why.empty()) std::cerr << "owval: " << why << "\n";
  SetExitCode(s.exit_code(StopSignal()));
}

// What a run is (pipeline::RunRequest), as `run` and a checkpoint's resumption take it. Returns
// the options, which --resume excludes: a resumed run has its checkpoint's own.
std::vector<CLI::Option*> AddRunFlags(CLI::App* cmd, pipeline::RunRequest* r) {
  const std::size_t before = cmd->get_options().size();
  cmd->add_option("config", r->config,
                  "Scenario name (owval scenario list) or Sibernetic configuration file")
      ->check(GivenName());
  AddTimeFlag(cmd, &r->time_s, " (steps = (int)(time/dt))");
  AddLogStepFlag(cmd, &r->log_step);
  AddOut(cmd, &r->out,
         "Output directory (position_buffer.txt and trajectory.h5, written as frames are "
         "produced)");
  std::string backends;
  for (const std::string& name : engine::KnownBackends())
    backends += (backends.empty() ? "" : ", ") + name;
  AddBackendFlag(cmd, &r->backend, ": " + backends + " (default pcisph; owval = pcisph)");
  AddIntegratorFlag(cmd, &r->integrator);
  cmd->add_option("--muscles", r->muscles,
                  "Muscle activations: auto (Sibernetic's rule: main_sim's swimming waves when "
                  "the configuration's name contains \"worm\"), waves, or off")
      ->check(CLI::IsMember({"auto", "waves", "off"}));
  cmd->add_flag("--apply-physical-parameters", r->apply_physical_parameters,
                "Apply the configuration's [physical parameters] block (Sibernetic ignores it)");
  AddConstantOverrides(cmd, &r->set, "; the result is then not reference-equivalent");
  cmd->add_flag("--no-fields", r->no_fields,
                "Record positions only (no velocity, density, pressure): faster");
  cmd->add_flag("--zarr", r->zarr, "Also write trajectory.zarr (OME-Zarr, zarr v2 layout)");
  cmd->add_option(
         "--checkpoint-every", r->checkpoint_every,
         "Write the solver's state to DIR/checkpoint/checkpoint.bin every N steps (pcisph, xpbd; "
         "a scheme that cannot checkpoint refuses it)")
      ->check(Count());
  const std::vector<CLI::Option*> all = cmd->get_options();
  return {all.begin() + std::ptrdiff_t(before), all.end()};
}

void SetUpRun(CLI::App& app) {
  auto a = std::make_shared<RunArgs>();
  pipeline::RunRequest& r = a->request;
  CLI::App* cmd = app.add_subcommand("run", "Phase 2/4: run the reference PCISPH engine");
  const std::vector<CLI::Option*> run_flags = AddRunFlags(cmd, &r);
  AddThreadsFlag(cmd, &a->options.threads,
                 " (default: every idle core; one below " +
                     std::to_string(engine::kFewestParticlesForThreads) + " particles)");
  AddJsonFlag(cmd, &a->json, "a summary");
  CLI::Option* resume =
      cmd->add_option("--resume", a->resume,
                      "Continue the checkpointed run in this output directory with its own "
                      "arguments; the outputs equal an uninterrupted run's byte for byte")
          ->check(CLI::ExistingDirectory);
  // `--resume DIR --time 5` ran the checkpoint's own time and said nothing.
  for (CLI::Option* flag : run_flags) resume->excludes(flag);
  cmd->add_flag("--stability", a->options.stability,
                "Apply the long-run stability gate to every frame as it is produced (" +
                    compare::DescribeStability(compare::LongRunStabilityOptions()) +
                    "): exit 1 when it fails");
  cmd->footer(
      "Exit codes: 0 done, 1 simulation failed (NaN: state dump in --out) or --stability gate "
      "failed, 2 bad input, 130 (SIGINT) or 143 (SIGTERM) interrupted (partial trajectory "
      "*.partial.txt/*.partial.h5 and a checkpoint left in --out; continue with --resume).");
  cmd->callback([a] { RunEngine(*a); });
}

const bool run_registered = RegisterCommand(&SetUpRun);

}  // namespace
}  // namespace owval::cli
