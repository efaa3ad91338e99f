#pragma once
// Between worm trajectories, WCON tracks and skeleton series.
#include <filesystem>
#include <nlohmann/json.hpp>

#include "owval/kinematics/skeleton.hpp"
#include "owval/trajectory/worm_formats.hpp"

namespace owval::kinematics {

// The WCON track of a worm trajectory: per frame the midline's non-empty bins, head first, and
// the centroid of the elastic particles, in the (z, x) body plane in mm (skeleton.hpp). settings
// go to metadata.software.settings (configuration hash, backend, ...). InputError when the
// trajectory is not a worm.
WormTrack TrackFromTrajectory(const Trajectory& trajectory,
                              const nlohmann::json& settings = nlohmann::json::object());

SkeletonSeries SkeletonsFromTrack(const WormTrack& track);

// A .wcon/.json file through ReadWcon, anything else as a trajectory (ReadTrajectory).
SkeletonSeries LoadSkeletons(const std::filesystem::path& path);

}  // namespace owval::kinematics
