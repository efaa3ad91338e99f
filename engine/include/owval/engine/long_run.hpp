#pragma once
// Long runs to files (owval run): frames streamed into the output directory as they are
// produced, so memory is O(particles) whatever the run's length; checkpoints; an interrupted run
// leaving a readable partial trajectory; resume with the same bytes as an uninterrupted run.
//
//   LongRunOptions files{.out = "out"};
//   RunSummary s = RunToFiles(config, run_options, files);   // s.interrupted: stopped early
//
// Outputs: out/position_buffer.txt (Sibernetic text, OpenCL layout) and out/trajectory.h5
// (owval HDF5 with velocities, density and pressure when run_options.record_fields), written
// under temporary names and renamed when complete. A run stopped by run_options.stop_requested
// writes a checkpoint, then renames what it wrote to out/position_buffer.partial.txt and
// out/trajectory.partial.h5 (HDF5 attribute partial = 1). A run that hits a NaN leaves the same
// partial files and the state dump (run_options.dump_dir) and rethrows SimulationError.
//
// Checkpoint (out/checkpoint/checkpoint.bin, written atomically every
// run_options.checkpoint_every steps and on a stop): format version, the caller's invocation
// text, the configuration's fingerprint, steps done, frames, each output's WriterCheckpoint
// (trajectory/writer.hpp), the solver's state (Solver::SaveState) and the CRC-32 of all of
// that (a flipped byte is refused, not resumed from). Resuming
// (LongRunOptions::resume) continues the outputs from there, whether the run was killed
// (temporary files) or interrupted (partial files); what it writes is byte for byte what an
// uninterrupted run writes (text bytes, HDF5 dataset values). A run that completes removes
// out/checkpoint/.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

#include "owval/base/atomic_output.hpp"
#include "owval/engine/run.hpp"

namespace owval::engine {

struct LongRunOptions {
  std::filesystem::path out;  // output directory
  // Continue from out/checkpoint/checkpoint.bin instead of starting at step 0.
  bool resume = false;
  // Saved in every checkpoint, returned by ReadCheckpointInvocation: how to repeat the run
  // (owval run stores its arguments as JSON).
  std::string invocation;
  // Sees every frame after it is written (a stability monitor); may be empty.
  std::function<void(const FrameView&)> on_frame;
  // Sees the trajectory's metadata once, before the first frame; may be empty.
  std::function<void(const Trajectory&)> on_begin;
  // When set, a completed run's text and HDF5 join this group and the caller commits it with
  // its other outputs; otherwise RunToFiles commits the two together.
  OutputGroup* outputs = nullptr;
};

// out/checkpoint/checkpoint.bin
std::filesystem::path CheckpointPath(const std::filesystem::path& out);
// The output files RunToFiles writes into `out`, in order (text, HDF5).
std::vector<std::filesystem::path> LongRunOutputs(const std::filesystem::path& out);

// The invocation text a checkpoint holds. InputError naming the file when it is missing or not
// a checkpoint of this format version.
std::string ReadCheckpointInvocation(const std::filesystem::path& out);

// Runs as engine::Run does, into files. With long_run.resume, run_options must describe the same
// run as the checkpointed one (same configuration: checked by fingerprint) and
// run_options.resume_state is ignored.
RunSummary RunToFiles(const SiberneticConfig& config, const RunOptions& run_options,
                      const LongRunOptions& long_run);

}  // namespace owval::engine
