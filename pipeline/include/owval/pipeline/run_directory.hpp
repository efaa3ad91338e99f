#pragma once
// `owval run` as a library call: a simulation streamed into an output directory
// (engine::RunToFiles) with the harness's outputs beside the engine's: the worm's
// worm_motion_log.txt and worm.wcon (kinematics), an OME-Zarr copy, an adaptive scheme's
// step_log.json, and the long-run stability gate applied to every frame as it is produced.
//
//   pipeline::RunRequest request;            // what defines the run (saved in checkpoints)
//   request.config = "demo1";  request.out = "out";  request.time_s = 0.2;
//   pipeline::RunDirectorySummary summary;
//   pipeline::RunIntoDirectory(config, request, {}, &summary);
//   std::cout << summary.ToJson().dump(2);
#include <cstddef>
#include <filesystem>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "owval/compare/stability.hpp"
#include "owval/engine/config.hpp"
#include "owval/engine/run.hpp"
#include "owval/trajectory/formats.hpp"
#include "owval/trajectory/trajectory.hpp"

namespace owval::pipeline {

// The arguments that define a run's outputs. A checkpoint keeps them, so that `--resume DIR`
// repeats the same run (only what changes no output byte may differ: threads, stability).
struct RunRequest {
  std::string config;  // scenario name or configuration path, as given
  double time_s = 0.05;
  int log_step = 1;
  std::string out;                   // output directory
  std::string backend = "pcisph";    // engine::KnownBackends()
  std::string integrator = "euler";  // euler | leapfrog
  std::string muscles = "auto";      // auto | waves | off
  std::vector<std::string> set;      // constant overrides, NAME=VALUE
  bool apply_physical_parameters = false;
  bool no_fields = false;  // positions only
  bool zarr = false;       // also trajectory.zarr
  std::size_t checkpoint_every = 0;

  nlohmann::json ToJson() const;
  // The request a checkpointed run in `out` was started with, `out` as its output directory.
  // InputError naming the checkpoint when it is missing or unreadable.
  static RunRequest FromCheckpoint(const std::string& out);
};

struct RunDirectoryOptions {
  bool resume = false;     // continue from out/checkpoint (the request must be the saved one)
  bool stability = false;  // apply compare::LongRunStabilityOptions() to every frame
  int threads = 0;         // 0: the engine's rule
  std::function<void(std::size_t done, std::size_t total)> on_step;  // progress; may be empty
  std::function<bool()> stop_requested;  // polled between steps; may be empty
};

struct RunDirectorySummary {
  engine::RunSummary run;
  std::string backend;               // canonical name
  std::vector<std::string> outputs;  // files written (partial names when interrupted)
  std::unique_ptr<compare::StabilityReport> stability;  // with options.stability
  std::string out;                                      // the output directory
  std::string configuration;  // the configuration's source (a file, or a generated scenario's)

  // What `owval run --json` prints.
  nlohmann::json ToJson(const std::string& configuration) const;
  // What `owval run` shows on stderr when the run returns (unless --quiet): the stability
  // table (with --stability) and "ran steps A to B in T s (N steps/s), F frames -> OUT".
  std::string ToText() const;
  // Why the run ends with a non-zero exit code, in one line, "" when it does not: interrupted
  // (with the --resume command to continue, or why there is none) or the stability gate failed.
  std::string FailureLine() const;
  // 0; 1 when the stability gate failed; 128 + `stop_signal` when interrupted (130 for SIGINT,
  // 143 for SIGTERM).
  int exit_code(int stop_signal) const;
};

// The worm's WCON (trajectory/worm_formats.hpp) from a trajectory, `settings` as its provenance
// and owval's version as the writing software: what `run` and `convert x.wcon` write. InputError
// when the trajectory is not a worm.
void WriteWormWcon(const Trajectory& t, const nlohmann::json& settings,
                   const std::filesystem::path& path);

// `owval convert`: the trajectory file `in` (any format OpenFrameSource reads, with `read`;
// `report` filled as ReadTrajectory fills it) written in the format `out`'s extension names, frame
// by frame (memory: a frame and a chunk of frames, never the trajectory), the bytes the
// whole-trajectory writers wrote: .wcon (a worm's WCON, InputError naming `in` for anything else;
// the file's provenance as its settings), .zarr (OME-Zarr), .h5/.hdf5 (owval HDF5, with the
// per-frame fields `in` holds), else Sibernetic text in `text_layout`. `out` is checked before
// `in` is read (an extension no writer takes, a path that is `in`: InputError); a bad frame
// midway leaves no `out`.
void ConvertTrajectoryFile(const std::filesystem::path& in, const TextReadOptions& read,
                           const std::filesystem::path& out, TextLayout text_layout,
                           TextReadReport* report = nullptr);

// The engine's options for the request: unknown backend, bad --set assignment: InputError.
engine::RunOptions EngineOptions(const RunRequest& request);

// Checks the output paths, runs, writes the harness outputs when the run completed. Bad input:
// InputError before any step; NaN: SimulationError with the state dump in request.out.
void RunIntoDirectory(const engine::SiberneticConfig& config, const RunRequest& request,
                      const RunDirectoryOptions& options, RunDirectorySummary* summary);
// The same for `owval run`: the request's configuration (a scenario name in `data_dir`, or a
// file) resolved and a progress line on stderr unless `quiet`. InputError when the request has
// no configuration or no output directory.
RunDirectorySummary RunNamedIntoDirectory(const RunRequest& request, RunDirectoryOptions options,
                                          const std::filesystem::path& data_dir, bool quiet);

}  // namespace owval::pipeline
