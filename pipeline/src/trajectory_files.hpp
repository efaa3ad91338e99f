#pragma once
// The pipeline's trajectories live in files, never whole in memory (memory O(particles),
// whatever the run's length): runs and copies are written frame by frame as they are produced,
// and every phase reads them back frame by frame (trajectory/frame_source.hpp).
#include <filesystem>
#include <memory>
#include <vector>

#include "owval/engine/run.hpp"
#include "owval/trajectory/formats.hpp"
#include "owval/trajectory/frame_source.hpp"
#include "owval/trajectory/track.hpp"

namespace owval::pipeline {

// Runs the engine, appending each frame to `destination` (owval HDF5, or Sibernetic text, by its
// extension) with the fields the run records. The file appears only when the run completes; an
// exception (bad input, NaN) leaves nothing.
engine::RunSummary RunIntoFile(const engine::SiberneticConfig& config,
                               const engine::RunOptions& options,
                               const std::filesystem::path& destination);

// Writes the trajectory file `source` (any format OpenFrameSource reads) into `destination`,
// frame by frame, with the per-frame fields the source holds: what WriteHdf5(ReadTrajectory())
// wrote, without holding the trajectory.
void CopyTrajectoryFile(const std::filesystem::path& source,
                        const std::filesystem::path& destination, const TextReadOptions& read = {});

// One tracked value a frame and the frames' times: all that fits, predictions and rms targets
// need of a trajectory (one double a frame).
struct TrackedSeries {
  std::vector<double> time_s;
  std::vector<double> value;
};
// A trajectory file read frame by frame, without a progress line (the pipeline prints its own).
std::unique_ptr<FrameSource> OpenQuietly(const std::filesystem::path& file);

// Read frame by frame. InputError when the track names nothing in the file.
TrackedSeries ReadTrackedSeries(const std::filesystem::path& file, const Track& track);

// What a fit needs of a run: every frame of only the particles the track follows (the particle,
// or its group's members in file order), 12 bytes a followed particle a frame. KeptTrack(track)
// reads from it the whole trajectory's tracked values, by the same arithmetic.
Trajectory RunKeepingTracked(const engine::SiberneticConfig& config,
                             const engine::RunOptions& options, const Track& track);
// The same from a trajectory file, frame by frame.
Trajectory ReadKeepingTracked(const std::filesystem::path& file, const Track& track);
// The track re-pointed at the kept particles (a group is every kept particle).
Track KeptTrack(const Track& track);

}  // namespace owval::pipeline
