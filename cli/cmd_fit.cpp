// owval fit: phase 5, parameters fitted by an optimiser with the convergence history saved.
#include <iostream>

#include "backend_flags.hpp"
#include "command.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/format.hpp"
#include "owval/base/progress.hpp"
#include "owval/base/stop_signals.hpp"
#include "owval/pipeline/fit_directory.hpp"
#include "run_flags.hpp"

namespace owval::cli {
namespace {

struct FitArgs {
  pipeline::FitRequest request;
  std::string config;
  TrackFlags track;
  bool json = false;
};

void RunFit(FitArgs& a) {
  pipeline::FitRequest& r = a.request;
  r.track = a.track.Over(Track{});
  r.quiet = QuietMode();
  pipeline::FitDirectorySummary summary;
  {
    const StopSignals signals;  // the fit stops after its current iteration, history kept
    pipeline::FitNamedIntoDirectory(r, a.config, DataDir(), StopRequested, &summary);
  }
  std::cout << (a.json ? summary.history.dump(2) + "\n" : summary.ToText());
  // Interrupted: 128 + the signal, as `run` (an interrupted fit is not a failed one).
  if (StopRequested())
    SetExitCode(128 + StopSignal());
  else if (!summary.converged)
    SetExitCode(kExitGateFailed);
}

void SetUpFit(CLI::App& app) {
  auto a = std::make_shared<FitArgs>();
  CLI::App* cmd = app.add_subcommand(
      "fit", "Phase 5: fit parameters with Ceres (or gradient descent), history saved");
  AddInput(cmd, "config", &a->config,
           "Scenario name or Sibernetic configuration (unused with --command)");
  cmd->add_option("--param", a->request.parameters,
                  "NAME=START[:log|:lin][:LOWER:UPPER], e.g. elasticity_coefficient=1.62e8:log")
      ->required();
  cmd->add_option("--target", a->request.targets,
                  "METRIC=VALUE[:scale=S][:weight=W][:ref=FILE]; METRIC: period, "
                  "half_amplitude, equilibrium, rms (finite-difference fits)");
  AddTrackFlags(cmd, &a->track, "track-", "Tracked");
  AddTimeFlag(cmd, &a->request.time_s, " per evaluation")->check(Positive());
  AddLogStepFlag(cmd, &a->request.log_step);
  cmd->add_option("--solver", a->request.solver,
                  "lm, dogleg or gd; with --gradient analytic|model-fd: lbfgs (default) or adam")
      ->check(CLI::IsMember({"lm", "dogleg", "gd", "lbfgs", "adam"}));
  cmd->add_option("--command", a->request.command,
                  "External simulator: {param} placeholders, {out} dir, {out_file}");
  cmd->add_option("--fit-backend", a->request.fit_backend,
                  "Fit this named command backend instead (--backends; each parameter as "
                  "{set:NAME}): owval checklist --fit-backend can rerun it, a --command fit not")
      ->check(GivenName());
  AddBackendsFileFlag(cmd, &a->request.backends_file, " of --fit-backend");
  cmd->add_option(
         "--threshold", a->request.threshold,
         "Stop when the loss is below this (default " + FormatNumber(a->request.threshold) + ")")
      ->check(NonNegative());
  cmd->add_option("--max-iterations", a->request.max_iterations, "Iteration cap")
      ->check(PositiveCount());
  cmd->add_option("--learning-rate", a->request.learning_rate,
                  "Gradient descent step in internal units")
      ->check(Positive());
  cmd->add_option("--patience", a->request.patience,
                  "--solver adam: stop after this many iterations without a 0.1% lower best loss "
                  "(0: never); the result is the best iterate")
      ->check(NonNegative());
  AddOut(cmd, &a->request.out, "Output directory (history.json, parameters.json, convergence.svg)")
      ->required();
  AddJsonFlag(cmd, &a->json, "the history");
  AddBackendFlag(cmd, &a->request.backend,
                 " of the finite-difference fit's engine runs (pcisph, the default, or xpbd)");
  cmd->add_option("--gradient", a->request.gradient,
                  "fd (finite differences of runs, any backend), analytic (XPBD's reverse "
                  "pass, Ceres L-BFGS) or model-fd (the same L-BFGS and model, central "
                  "differences instead of the reverse pass: the comparison run)")
      ->check(CLI::IsMember({"fd", "analytic", "model-fd"}));
  cmd->add_option("--reference", a->request.reference_file,
                  "analytic: trajectory the loss compares with (frames paired by step)")
      ->check(GivenName());
  cmd->add_option("--loss-group", a->request.loss_groups,
                  "analytic: group centroids (all axes) in the loss instead of the tracked "
                  "coordinate; repeatable");
  cmd->add_option("--loss-scale", a->request.loss_scale, "analytic: length scale of the loss (cu)")
      ->check(Positive());
  AddTapeCheckpointFlag(cmd, &a->request.checkpoint_every, " (--gradient analytic)");
  cmd->add_option("--window", a->request.window,
                  "analytic: truncated backpropagation window (steps)");
  cmd->add_option("--clip-norm", a->request.clip_norm,
                  "analytic: per-step state-gradient norm clip (0: off)")
      ->check(NonNegative());
  cmd->callback([a] { RunFit(*a); });
}

const bool fit_registered = RegisterCommand(&SetUpFit);

}  // namespace
}  // namespace owval::cli
