#include "owval/kinematics/worm_track.hpp"

#include "owval/base/errors.hpp"
#include "owval/kinematics/midline.hpp"
#include "owval/trajectory/formats.hpp"

namespace owval::kinematics {

WormTrack TrackFromTrajectory(const Trajectory& t, const nlohmann::json& settings) {
  const SkeletonSeries s = SkeletonsFromTrajectory(t);
  const std::vector<std::size_t> elastic = GroupIndices(t, "elastic");
  const double to_mm = static_cast<double>(kSiberneticSimulationScale) * 1000.0;
  WormTrack track;
  track.software_settings = settings;
  track.owval = {{"body_plane",
                  "WCON x = simulation z, WCON y = simulation x (mm); gravity "
                  "along simulation -y"},
                 {"midline", "Sibernetic's worm_motion_log bins 51..149 (non-empty), head first"},
                 {"centroid", "mean of the elastic particles"},
                 {"provenance", t.provenance}};
  for (std::size_t f = 0; f < t.frame_count(); ++f) {
    track.time_s.push_back(t.time_s[f]);
    std::vector<float> x, y;
    for (const Point2& p : s.skeletons[f]) {
      x.push_back(static_cast<float>(p[0]));
      y.push_back(static_cast<float>(p[1]));
    }
    track.x_mm.push_back(std::move(x));
    track.y_mm.push_back(std::move(y));
    const std::array<double, 3> c = Centroid(t, f, elastic);
    track.cx_mm.push_back(c[2] * to_mm);
    track.cy_mm.push_back(c[0] * to_mm);
  }
  return track;
}

SkeletonSeries SkeletonsFromTrack(const WormTrack& track) {
  SkeletonSeries s;
  s.time_s = track.time_s;
  for (std::size_t i = 0; i < track.time_s.size(); ++i) {
    Skeleton k;
    for (std::size_t j = 0; j < track.x_mm[i].size(); ++j)
      k.push_back({track.x_mm[i][j], track.y_mm[i][j]});
    s.skeletons.push_back(std::move(k));
  }
  return s;
}

SkeletonSeries LoadSkeletons(const std::filesystem::path& path) {
  const std::string ext = path.extension().string();
  if (ext == ".wcon" || ext == ".json") return SkeletonsFromTrack(ReadWcon(path));
  TextReadOptions quiet;
  quiet.quiet = true;
  const Trajectory t = ReadTrajectory(path, quiet);
  if (!IsWorm(t)) throw InputError(path.string(), 0, kNotAWorm);
  return SkeletonsFromTrajectory(t);
}

}  // namespace owval::kinematics
