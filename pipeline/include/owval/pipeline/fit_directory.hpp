#pragma once
// `owval fit` (phase 5) as a library call: parameters fitted by an optimiser, the history written
// to `out/history.json` after every iteration (a long fit can be watched and loses nothing), and
// at the end the history, parameters.json and convergence.svg, which appear together.
//
// Two kinds of fit:
//   - finite differences ("fd"): runs of the engine (any backend) or of an external command,
//     scored against targets (period, half-amplitude, ...) by Ceres or gradient descent;
//   - "analytic" (XPBD's reverse pass) or "model-fd" (the same model and L-BFGS/Adam, central
//     differences instead of the reverse pass): a loss against a reference trajectory.
//
//   pipeline::FitRequest request;
//   request.parameters = {"elasticity_coefficient=1.62e8:log"};
//   request.targets = {"period=0.7246e-3"};
//   request.out = "fit";
//   pipeline::FitDirectorySummary summary;
//   pipeline::FitIntoDirectory(request, &config, nullptr, {}, &summary);
#include <cstddef>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "owval/engine/config.hpp"
#include "owval/trajectory/frame_source.hpp"
#include "owval/trajectory/track.hpp"

namespace owval::pipeline {

struct FitRequest {
  std::vector<std::string> parameters;  // NAME=START[:log|:lin][:LOWER:UPPER]
  std::vector<std::string> targets;     // fd: METRIC=VALUE[:scale=S][:weight=W][:ref=FILE]
  Track track;                          // the tracked quantity of targets and analytic losses
  double time_s = 0.05;                 // simulated time per evaluation
  int log_step = 1;
  std::string solver = "lm";  // fd: lm | dogleg | gd; analytic: lbfgs (also "lm") | adam
  std::string command;        // fd: an external simulator instead of the engine
  // fd: a named backend's command instead (docs/fit_history.md, kind "backend"): the registry
  // entry `fit_backend` of `backends_file` (else ./owval-backends.json, else the XDG file), run
  // with the configuration, time and log step, each parameter as {set:NAME}. The PR checklist
  // can rerun such a fit through the reviewer's own entry; a --command fit it cannot.
  std::string backends_file, fit_backend;
  std::string out;          // output directory
  double threshold = 1e-4;  // stop when the loss is below
  int max_iterations = 20;
  double learning_rate = 0.5;
  int patience = 10;  // --solver adam: iterations without a 0.1% better loss before it stops
  std::string gradient = "fd";  // fd | analytic | model-fd
  // fd: the engine scheme of the evaluations ("": pcisph). Refused with --command,
  // --fit-backend and the gradient fits, which run no engine scheme it could name: a fit that
  // silently ran something else than the scheme asked for would be recorded as that scheme's.
  std::string backend;
  // analytic: group centroids (every axis) in the loss instead of the tracked coordinate.
  std::vector<std::string> loss_groups;
  double loss_scale = 1;                          // cu
  std::size_t checkpoint_every = 10, window = 0;  // reverse pass: stored states, TBPTT window
  double clip_norm = 0;                           // per-step state-gradient norm clip (0: off)
  bool quiet = false;                             // no progress line per iteration
  // analytic, model-fd: the file `reference` was opened from, recorded in history.json with its
  // hash so that the PR checklist can rerun the loss at the best iterate (required there).
  std::string reference_file;
};

struct FitDirectorySummary {
  nlohmann::json history;                              // what history.json holds
  std::string brief;                                   // one line: how it ended
  std::vector<std::pair<std::string, double>> values;  // the fitted parameters
  bool converged = false;

  // The brief, then "  NAME = VALUE" per fitted parameter, a line each.
  std::string ToText() const;
};

// history.json records what was simulated ("simulation", docs/fit_history.md) and the
// configuration is written beside it (out/configuration.txt), so that the best iterate can be
// rerun (owval checklist, item 6).
// `config`: the simulation (not read by fd fits with a command); `reference`: the analytic and
// model-fd fits' trajectory (required there), read frame by frame up to the fitted time: the
// loss keeps the tracked coordinate or the group centroids of each frame, never the frames.
// An fd fit's evaluations and rms references keep only their tracked series. `cancelled` is
// polled between evaluations (fd) or iterations. InputError naming the flag for a request that
// cannot run.
void FitIntoDirectory(const FitRequest& request, const engine::SiberneticConfig* config,
                      FrameSource* reference, const std::function<bool()>& cancelled,
                      FitDirectorySummary* summary);
// The same for `owval fit`: `config_name` (a scenario name in `data_dir`, or a configuration
// file) resolved where an engine or a named backend runs (not for an fd fit with a command), and
// for the analytic and model-fd fits the reference opened from request.reference_file (any
// format, frame by frame; progress lines unless request.quiet).
void FitNamedIntoDirectory(const FitRequest& request, const std::string& config_name,
                           const std::filesystem::path& data_dir,
                           const std::function<bool()>& cancelled, FitDirectorySummary* summary);

}  // namespace owval::pipeline
