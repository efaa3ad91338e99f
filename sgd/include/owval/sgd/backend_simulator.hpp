#pragma once
// A named backend's command (backends/registry.hpp, docs/backends.md) as a fit's simulator:
// each evaluation runs the registry entry's `command` with {config} the fit's recorded
// configuration file, {time}/{time_step}/{log_step} the fit's run, and every fitted parameter
// as {set:NAME}, then keeps the tracked series of the trajectory it wrote. The same call reruns
// a fit's best iterate for the PR checklist, through the entry the *caller* names (never a
// template the history carries: that would run the pull request's program on the reviewer's
// machine).
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "owval/backends/registry.hpp"
#include "owval/sgd/targets.hpp"

namespace owval::sgd {

// What one backend evaluation runs, besides the parameters.
struct BackendRun {
  std::filesystem::path configuration;  // the file given as {config}
  double duration_s = 0;                // {time}
  double time_step_s = 2e-5;            // {time_step}: Sibernetic's default
  int log_step = 1;                     // {log_step}
};

// InputError (one line, naming the backend) unless `backend` can be fitted over `parameters`:
// a command backend whose template names each parameter as {set:NAME} (a parameter the command
// never receives would leave the loss flat).
void CheckFittableBackend(const backends::Backend& backend,
                          const std::vector<std::string>& parameter_names);

// The run of `backend` at `values` (each parameter's value with 17 significant digits, which
// gives the double back exactly), its tracked series read frame by frame; the run's directory is
// removed when the series is read. Never the entry's store fallback: a recorded run does not
// depend on the parameters. InputError when the command fails or writes no readable trajectory.
TrackedSeries RunBackendTrackedSeries(const backends::Backend& backend, const BackendRun& run,
                                      const std::vector<std::string>& parameter_names,
                                      const std::vector<double>& values, const Track& track);

// RunBackendTrackedSeries per evaluation (safe to call concurrently: each run has its own
// directory).
Simulator BackendSimulator(backends::Backend backend, BackendRun run,
                           std::vector<Parameter> parameters);

// "simulation" of a fit of a named backend: {"kind": "backend", "name", "command" (the template
// the fit ran: provenance only, never run by the checklist), configuration, duration_s,
// time_step_s, log_step}.
nlohmann::json BackendSimulationJson(const backends::Backend& backend, const BackendRun& run,
                                     const nlohmann::json& configuration);

}  // namespace owval::sgd
