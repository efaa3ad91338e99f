#include "owval/kinematics/worm_track.hpp"

#include <functional>
#include <memory>
#include <optional>
#include <utility>

#include "owval/base/errors.hpp"
#include "owval/kinematics/midline.hpp"
#include "owval/trajectory/frame_source.hpp"

namespace owval::kinematics {

WormTrack TrackHead(const Trajectory& header, const nlohmann::json& settings) {
  WormTrack track;
  track.software_settings = settings;
  track.owval = {{"body_plane",
                  "WCON x = simulation z, WCON y = simulation x (mm); gravity "
                  "along simulation -y"},
                 {"midline", "Sibernetic's worm_motion_log bins 51..149 (non-empty), head first"},
                 {"centroid", "mean of the elastic particles"},
                 {"provenance", header.provenance}};
  return track;
}

TrackPoint TrackPointAt(const Trajectory& t, std::size_t frame,
                        const std::vector<std::size_t>& elastic) {
  const double to_mm = static_cast<double>(kSiberneticSimulationScale) * 1000.0;
  TrackPoint point{t.time_s[frame], {}, {}, 0, 0};
  for (const Point2& p : SkeletonAt(t, frame)) {
    point.x_mm.push_back(static_cast<float>(p[0]));
    point.y_mm.push_back(static_cast<float>(p[1]));
  }
  const std::array<double, 3> c = Centroid(t, frame, elastic);
  point.cx_mm = c[2] * to_mm;
  point.cy_mm = c[0] * to_mm;
  return point;
}

WormTrack TrackFromTrajectory(const Trajectory& t, const nlohmann::json& settings) {
  if (!IsWorm(t))
    throw InputError(
        "trajectory has no worm body (no elastic particles with midline codes 2.1xxx)");
  const std::vector<std::size_t> elastic = GroupIndices(t, "elastic");
  WormTrack track = TrackHead(t, settings);
  for (std::size_t f = 0; f < t.frame_count(); ++f) {
    TrackPoint p = TrackPointAt(t, f, elastic);
    track.time_s.push_back(p.time_s);
    track.x_mm.push_back(std::move(p.x_mm));
    track.y_mm.push_back(std::move(p.y_mm));
    track.cx_mm.push_back(p.cx_mm);
    track.cy_mm.push_back(p.cy_mm);
  }
  return track;
}

namespace {

WormTrack VersionedHead(const Trajectory& header, const nlohmann::json& settings,
                        const std::string& software_version) {
  WormTrack head = TrackHead(header, settings);
  head.software_version = software_version;
  return head;
}

}  // namespace

WormWconWriter::WormWconWriter(const std::filesystem::path& path, const Trajectory& header,
                               const nlohmann::json& settings, const std::string& software_version)
    : elastic_(GroupIndices(header, "elastic")),
      wcon_(path, VersionedHead(header, settings, software_version), true) {
  if (!IsWorm(header)) throw InputError(path.string(), 0, kNotAWorm);
}

void WormWconWriter::Append(const Trajectory& trajectory, std::size_t frame) {
  const TrackPoint p = TrackPointAt(trajectory, frame, elastic_);
  wcon_.Append(p.time_s, p.x_mm, p.y_mm, p.cx_mm, p.cy_mm);
}

namespace {

// What Analyse needs, said with the file's name (Analyse itself knows no file): two frames, and
// a skeleton of two points at each (a WCON may hold one point a time, a centroid track).
// short_frame: the first frame whose skeleton has fewer than 2 points, and its point count.
using ShortFrame = std::optional<std::pair<std::size_t, std::size_t>>;

void RefuseUnanalysable(std::size_t frames, const ShortFrame& short_frame,
                        const std::filesystem::path& path) {
  if (frames < 2)
    throw InputError(
        path.string(), 0,
        "holds " + std::to_string(frames) + " frame(s): kinematics need at least 2 frames");
  if (short_frame)
    throw InputError(path.string(), 0,
                     "frame " + std::to_string(short_frame->first) + "'s skeleton has " +
                         std::to_string(short_frame->second) +
                         " point(s): kinematics need at least 2 midline points a frame");
}

void CheckAnalysable(const SkeletonSeries& s, const std::filesystem::path& path) {
  ShortFrame short_frame;
  for (std::size_t f = 0; f < s.skeletons.size() && !short_frame; ++f)
    if (s.skeletons[f].size() < 2) short_frame.emplace(f, s.skeletons[f].size());
  RefuseUnanalysable(s.time_s.size(), short_frame, path);
}

Skeleton SkeletonOf(const std::vector<float>& x_mm, const std::vector<float>& y_mm) {
  Skeleton k;
  for (std::size_t j = 0; j < x_mm.size(); ++j) k.push_back({x_mm[j], y_mm[j]});
  return k;
}
Skeleton TrackSkeleton(const WormTrack& track, std::size_t i) {
  return SkeletonOf(track.x_mm[i], track.y_mm[i]);
}

// Each frame's time and skeleton in order, one at a time: a .wcon/.json through WconReader,
// anything else as a trajectory read frame by frame (OpenFrameSource).
void ForEachSkeleton(const std::filesystem::path& path,
                     const std::function<void(double, const Skeleton&)>& observe) {
  const std::string ext = path.extension().string();
  if (ext == ".wcon" || ext == ".json") {
    WconReader reader(path);
    WconTimePoint point;
    while (reader.Next(&point)) observe(point.time_s, SkeletonOf(point.x_mm, point.y_mm));
    return;
  }
  TextReadOptions quiet;
  quiet.quiet = true;
  const std::unique_ptr<FrameSource> frames = OpenFrameSource(path, quiet);
  if (!IsWorm(frames->header())) throw InputError(path.string(), 0, kNotAWorm);
  ForEachFrameSkeleton(*frames, observe);
}

}  // namespace

SkeletonSeries SkeletonsFromTrack(const WormTrack& track) {
  SkeletonSeries s;
  s.time_s = track.time_s;
  for (std::size_t i = 0; i < track.time_s.size(); ++i)
    s.skeletons.push_back(TrackSkeleton(track, i));
  return s;
}

SkeletonSeries LoadSkeletons(const std::filesystem::path& path) {
  SkeletonSeries s;
  ForEachSkeleton(path, [&](double time_s, const Skeleton& skeleton) {
    s.time_s.push_back(time_s);
    s.skeletons.push_back(skeleton);
  });
  CheckAnalysable(s, path);
  return s;
}

Report AnalyseFile(const std::filesystem::path& path, const Options& options) {
  Analyser analyser(options);
  ShortFrame short_frame;
  const auto observe = [&](double time_s, const Skeleton& skeleton) {
    if (skeleton.size() < 2 && !short_frame)
      short_frame.emplace(analyser.frames(), skeleton.size());
    analyser.Observe(time_s, skeleton);
  };
  ForEachSkeleton(path, observe);
  RefuseUnanalysable(analyser.frames(), short_frame, path);
  return analyser.Finish();
}

}  // namespace owval::kinematics
