#pragma once
// The pipeline's trajectories live in files, never whole in memory (memory O(particles),
// whatever the run's length): runs and copies are written frame by frame as they are produced,
// and every phase reads them back frame by frame (trajectory/frame_source.hpp).
#include <filesystem>
#include <memory>

#include "owval/engine/run.hpp"
#include "owval/trajectory/formats.hpp"
#include "owval/trajectory/frame_source.hpp"
#include "owval/trajectory/track.hpp"
#include "owval/trajectory/tracked_series.hpp"

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

// A trajectory file read frame by frame, without a progress line (the pipeline prints its own).
std::unique_ptr<FrameSource> OpenQuietly(const std::filesystem::path& file);

// Its tracked series, read frame by frame. InputError when the track names nothing in the file.
TrackedSeries ReadTrackedSeries(const std::filesystem::path& file, const Track& track);

}  // namespace owval::pipeline
