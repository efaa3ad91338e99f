#pragma once
// Between worm trajectories, WCON tracks and skeleton series.
#include <filesystem>
#include <nlohmann/json.hpp>

#include "owval/kinematics/kinematics.hpp"
#include "owval/kinematics/skeleton.hpp"
#include "owval/trajectory/worm_formats.hpp"

namespace owval::kinematics {

// The WCON track of a worm trajectory: per frame the midline's non-empty bins, head first, and
// the centroid of the elastic particles, in the (z, x) body plane in mm (skeleton.hpp). settings
// go to metadata.software.settings (configuration hash, backend, ...). InputError when the
// trajectory is not a worm.
WormTrack TrackFromTrajectory(const Trajectory& trajectory,
                              const nlohmann::json& settings = nlohmann::json::object());

// TrackFromTrajectory's parts, for frames read one at a time (the same numbers): the track
// without time points, and one frame's time point (`elastic`: GroupIndices(header, "elastic")).
WormTrack TrackHead(const Trajectory& header,
                    const nlohmann::json& settings = nlohmann::json::object());
struct TrackPoint {
  double time_s;
  std::vector<float> x_mm, y_mm;  // the skeleton, head first
  double cx_mm, cy_mm;            // the elastic particles' centroid
};
TrackPoint TrackPointAt(const Trajectory& trajectory, std::size_t frame,
                        const std::vector<std::size_t>& elastic);

// The worm's WCON written as frames come (WconWriter): the bytes of
// WriteWcon(TrackFromTrajectory(trajectory, settings)) with `software_version`, memory one frame.
class WormWconWriter {
 public:
  // `header`: types and provenance. InputError naming `path` when it is not a worm.
  WormWconWriter(const std::filesystem::path& path, const Trajectory& header,
                 const nlohmann::json& settings, const std::string& software_version);
  void Append(const Trajectory& trajectory, std::size_t frame);
  void Commit() { wcon_.Commit(); }

 private:
  std::vector<std::size_t> elastic_;
  WconWriter wcon_;
};

SkeletonSeries SkeletonsFromTrack(const WormTrack& track);

// A .wcon/.json file through ReadWcon, anything else as a trajectory read frame by frame
// (OpenFrameSource: memory holds the skeletons, not the particles). InputError naming the file
// unless Analyse can use it: at least 2 frames, each skeleton of at least 2 points.
SkeletonSeries LoadSkeletons(const std::filesystem::path& path);

// Analyse(LoadSkeletons(path)), the same report and refusals, frame by frame into an Analyser: a
// trajectory's memory is one frame and the Analyser's few doubles a frame, never the skeletons.
// A WCON is read whole by ReadWcon (its track, as LoadSkeletons), then analysed time point by
// time point.
Report AnalyseFile(const std::filesystem::path& path, const Options& options = {});

}  // namespace owval::kinematics
