#include "owval/kinematics/side_files.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "log_lines.hpp"
#include "owval/base/errors.hpp"
#include "owval/kinematics/midline.hpp"
#include "owval/kinematics/worm_track.hpp"

namespace owval::kinematics {
namespace {

// 1e-3 cu in mm: the caller's-reference gate's tolerance, at Sibernetic's float scale.
const double kCuTolerance_mm = 1e-3 * static_cast<double>(kSiberneticSimulationScale) * 1e3;
constexpr double kRelativeTolerance = 1e-5;  // two 6-digit prints, 5e-6 each
constexpr double kTimeTolerance = 0.01;      // of the mean frame interval

double Allowance_mm(double value_mm) {
  return kRelativeTolerance * std::abs(value_mm) + kCuTolerance_mm;
}

double MeanInterval_s(const std::vector<double>& time_s) {
  if (time_s.size() < 2) return 0;
  return (time_s.back() - time_s.front()) / double(time_s.size() - 1);
}

std::string Format(const char* format, double a, double b = 0, double c = 0, double d = 0,
                   double e = 0) {
  char buffer[256];
  std::snprintf(buffer, sizeof buffer, format, a, b, c, d, e);
  return buffer;
}

TrackAgreement CountMismatch(std::size_t points, std::size_t frames) {
  TrackAgreement a;
  a.worst_fraction_of_allowance = INFINITY;
  a.detail =
      std::to_string(points) + " time points, the trajectory " + std::to_string(frames) + " frames";
  return a;
}

// A side file's time points held to the trajectory's frames of the same index, one at a time
// (memory: one frame and one time point).
class Lockstep {
 public:
  explicit Lockstep(FrameSource& trajectory)
      : traj_(trajectory),
        elastic_(GroupIndices(trajectory.header(), "elastic")),
        allowed_s_(kTimeTolerance * MeanInterval_s(trajectory.header().time_s)) {
    if (!IsWorm(trajectory.header())) throw InputError(kNotAWorm);
  }

  // The file's next time point; `centroid`: whether it has cx, cy.
  void Add(const WconTimePoint& point, bool centroid) {
    const std::size_t i = points_++;
    if (i >= traj_.frame_count() || !mismatch_.empty()) return;  // counted, not compared
    const double frame_s = traj_.header().time_s[i];
    if (std::abs(point.time_s - frame_s) > allowed_s_) {
      mismatch_ = "time point " + std::to_string(i) +
                  Format(" at t %.9g s, the trajectory's frame at %.9g s", point.time_s, frame_s);
      return;
    }
    const FrameRef frame = traj_.Frame(i);
    const TrackPoint expected = TrackPointAt(frame.trajectory, frame.frame, elastic_);
    if (point.x_mm.size() != expected.x_mm.size()) {
      mismatch_ = "time point " + std::to_string(i) + ": " + std::to_string(point.x_mm.size()) +
                  " skeleton points, the trajectory " + std::to_string(expected.x_mm.size());
      return;
    }
    centroid_ = centroid;
    CompareTimePoint(point, expected, centroid);
  }

  TrackAgreement Result() const {
    if (points_ != traj_.frame_count()) return CountMismatch(points_, traj_.frame_count());
    TrackAgreement a;
    if (!mismatch_.empty()) {
      a.worst_fraction_of_allowance = INFINITY;
      a.detail = mismatch_;
      return a;
    }
    a.agrees = failing_ == 0;
    a.worst_fraction_of_allowance = worst_;
    a.detail = std::to_string(points_) + " time points; " + std::to_string(failing_) +
               " disagree with the trajectory's skeleton" + (centroid_ ? " and centroid" : "") +
               Format("; worst %.3g of its allowance", worst_) + worst_where_;
    return a;
  }

 private:
  // Every skeleton point's and the centroid's distance to the trajectory's, in allowances.
  void CompareTimePoint(const WconTimePoint& got, const TrackPoint& expected, bool centroid) {
    bool failing = false;
    const auto add = [&](double fraction, const auto& where) {
      failing = failing || !(fraction <= 1);
      if (fraction > worst_ || std::isnan(fraction)) {
        worst_ = std::isnan(fraction) ? INFINITY : fraction;
        worst_where_ = Format(" at t %.6g s, ", expected.time_s) + where();
      }
    };
    for (std::size_t k = 0; k < got.x_mm.size(); ++k) {
      const double x = got.x_mm[k], y = got.y_mm[k];
      const double ex = expected.x_mm[k], ey = expected.y_mm[k];
      add(std::max(std::abs(x - ex) / Allowance_mm(ex), std::abs(y - ey) / Allowance_mm(ey)), [&] {
        return "point " + std::to_string(k) +
               Format(": (%.7g, %.7g) mm, the trajectory (%.7g, %.7g) mm", x, y, ex, ey);
      });
    }
    if (centroid) {
      const double ex = expected.cx_mm, ey = expected.cy_mm;
      add(std::max(std::abs(got.cx_mm - ex) / Allowance_mm(ex),
                   std::abs(got.cy_mm - ey) / Allowance_mm(ey)),
          [&] {
            return Format("centroid (%.9g, %.9g) mm, the trajectory (%.9g, %.9g) mm", got.cx_mm,
                          got.cy_mm, ex, ey);
          });
    }
    if (worst_where_.empty()) worst_where_ = Format(" at t %.6g s", expected.time_s);
    failing_ += failing;
  }

  FrameSource& traj_;
  std::vector<std::size_t> elastic_;
  double allowed_s_;
  std::size_t points_ = 0, failing_ = 0;
  bool centroid_ = false;
  std::string mismatch_;  // the first time or point count that differs
  double worst_ = 0;
  std::string worst_where_;  // the worst value's time and values
};

// One line of worm_motion_log.txt into `point` (time, non-empty bins' X: and Y: means); false
// for a blank line. InputError naming the file and line on a malformed line.
bool ParseLogLine(const std::string& line, std::size_t number, const std::filesystem::path& path,
                  WconTimePoint* point) {
  if (line.find_first_not_of(" \t\r\n") == std::string::npos) return false;  // a blank line
  std::istringstream fields(line);
  std::string label;
  std::array<std::array<double, kMidlineBins>, 3> block{};
  // Every field is checked: a blank or cut line has no bins, which the loop below would index.
  const auto malformed = [&] {
    return InputError(path.string(), number,
                      "expected t, then X:, Y:, Z: each with 99 bin means (mm)");
  };
  if (!(fields >> point->time_s) || !std::isfinite(point->time_s)) throw malformed();
  for (int b = 0; b < 3; ++b) {
    if (!(fields >> label) || label != std::string(1, char('X' + b)) + ":") throw malformed();
    for (int k = 0; k < kMidlineBins; ++k)
      if (!(fields >> block[b][k])) throw malformed();
  }
  point->x_mm.clear();
  point->y_mm.clear();
  for (int k = 0; k < kMidlineBins; ++k) {
    if (block[0][k] == 0 && block[1][k] == 0 && block[2][k] == 0) continue;  // empty bin
    point->x_mm.push_back(static_cast<float>(block[0][k]));                  // mean z
    point->y_mm.push_back(static_cast<float>(block[1][k]));                  // mean x
  }
  return true;
}

// worm_motion_log.txt[.gz] a line at a time (LogLines), each parsed into a time point.
class MotionLogLines {
 public:
  explicit MotionLogLines(std::filesystem::path path)
      : lines_(std::move(path), "t, then X:, Y:, Z: each with 99 bin means (mm)") {}

  // The next non-blank line's time point; false at the end of the file.
  bool Next(WconTimePoint* point) {
    while (lines_.Next(&line_))
      if (ParseLogLine(line_, lines_.number(), lines_.path(), point)) return true;
    return false;
  }

 private:
  LogLines lines_;
  std::string line_;
};

}  // namespace

TrackAgreement CompareWithTrajectory(const WormTrack& track, FrameSource& trajectory) {
  const bool centroid = !track.cx_mm.empty();
  if (centroid &&
      (track.cx_mm.size() != track.time_s.size() || track.cy_mm.size() != track.time_s.size()))
    throw InputError("track: cx and cy need one value per time point");
  Lockstep lockstep(trajectory);
  WconTimePoint point;
  for (std::size_t i = 0; i < track.time_s.size(); ++i) {
    point.time_s = track.time_s[i];
    point.x_mm = track.x_mm.at(i);
    point.y_mm = track.y_mm.at(i);
    point.cx_mm = centroid ? track.cx_mm[i] : 0;
    point.cy_mm = centroid ? track.cy_mm[i] : 0;
    lockstep.Add(point, centroid);
  }
  return lockstep.Result();
}

TrackAgreement CompareWconWithTrajectory(const std::filesystem::path& wcon,
                                         FrameSource& trajectory) {
  WconReader points(wcon);
  return CompareWconWithTrajectory(points, trajectory);
}

TrackAgreement CompareWconWithTrajectory(WconReader& points, FrameSource& trajectory) {
  Lockstep lockstep(trajectory);
  // Known before any frame is read: the count decides, as it does for the log at its end.
  if (points.size() != trajectory.frame_count())
    return CountMismatch(points.size(), trajectory.frame_count());
  points.Rewind();
  WconTimePoint point;
  while (points.Next(&point)) lockstep.Add(point, points.has_centroid());
  return lockstep.Result();
}

TrackAgreement CompareWormMotionLogWithTrajectory(const std::filesystem::path& log,
                                                  FrameSource& trajectory) {
  MotionLogLines lines(log);
  Lockstep lockstep(trajectory);
  WconTimePoint point;
  while (lines.Next(&point)) lockstep.Add(point, false);
  return lockstep.Result();
}

namespace {

// The first disagreement in frame count, times or types between a store and its trajectory, or
// "" when they agree.
std::string StoreHeaderMismatch(const OmeZarrReader& store, FrameSource& traj) {
  const Trajectory& h = traj.header();
  if (store.frame_count() != traj.frame_count() || store.particle_count() != h.particle_count())
    return std::to_string(store.frame_count()) + " frames of " +
           std::to_string(store.particle_count()) + " particles, the trajectory " +
           std::to_string(traj.frame_count()) + " of " + std::to_string(h.particle_count());
  const double allowed_s = kTimeTolerance * MeanInterval_s(h.time_s);
  for (std::size_t f = 0; f < store.frame_count(); ++f)
    if (std::abs(store.time_s()[f] - h.time_s[f]) > allowed_s)
      return "frame " + std::to_string(f) +
             Format(" at t %.9g s, the trajectory's at %.9g s", store.time_s()[f], h.time_s[f]);
  for (std::size_t i = 0; i < h.particle_count(); ++i)
    if (!(std::abs(store.type()[i] - h.type[i]) <= kRelativeTolerance * std::abs(h.type[i])))
      return "particle " + std::to_string(i) +
             Format(" type %.7g, the trajectory's %.7g", store.type()[i], h.type[i]);
  return "";
}

// A trajectory's configuration units are Sibernetic's (kSiberneticSimulationScale m each): a
// store saying its micrometres were converted at another scale shows the viewer a worm of
// another size, so it is refused rather than compared at a scale assumed. 1e-6 relative: the
// scale printed as a double against Sibernetic's float.
void CheckStoreScale(const OmeZarrReader& store) {
  const double sibernetic_m = static_cast<double>(kSiberneticSimulationScale);
  const double recorded_m = store.simulation_scale_m();
  if (recorded_m != 0 && std::abs(recorded_m / sibernetic_m - 1) > 1e-6)
    throw InputError((store.path() / ".zattrs").string(), 0,
                     Format("@owval.simulation_scale_m: %.9g m per configuration unit, but the "
                            "trajectory's are Sibernetic's %.9g m",
                            recorded_m, sibernetic_m));
}

}  // namespace

TrackAgreement CompareWithTrajectory(OmeZarrReader& store, FrameSource& traj) {
  TrackAgreement a;
  a.detail = StoreHeaderMismatch(store, traj);
  if (!a.detail.empty()) {
    a.worst_fraction_of_allowance = INFINITY;
    return a;
  }
  CheckStoreScale(store);
  const double to_um = static_cast<double>(kSiberneticSimulationScale) * 1e6;
  std::size_t failing_frames = 0, worst_frame = 0, worst_value = 0;
  for (std::size_t f = 0; f < traj.frame_count(); ++f) {
    const FrameRef frame = traj.Frame(f);
    const float* cu = frame.trajectory.position(frame.frame, 0);
    const float* um = store.FrameMicrometres(f);
    bool failing = false;
    for (std::size_t k = 0; k < store.particle_count() * 3; ++k) {
      const double expected_um = double(cu[k]) * to_um;
      const double fraction = std::abs(um[k] - expected_um) /
                              (kRelativeTolerance * std::abs(expected_um) + 1e-3 * to_um);
      failing = failing || !(fraction <= 1);
      if (!(fraction <= a.worst_fraction_of_allowance)) {
        a.worst_fraction_of_allowance = std::isnan(fraction) ? INFINITY : fraction;
        worst_frame = f, worst_value = k;
      }
    }
    failing_frames += failing;
  }
  a.agrees = failing_frames == 0;
  a.detail = std::to_string(traj.frame_count()) + " frames; " + std::to_string(failing_frames) +
             " disagree with the trajectory's positions; worst" +
             Format(" %.3g of its allowance", a.worst_fraction_of_allowance) + " at frame " +
             std::to_string(worst_frame) + ", particle " + std::to_string(worst_value / 3) +
             " axis " + std::to_string(worst_value % 3);
  return a;
}

WormTrack ReadWormMotionLog(const std::filesystem::path& path) {
  MotionLogLines lines(path);
  WormTrack track;
  WconTimePoint point;
  while (lines.Next(&point)) AppendTimePoint(point, false, &track);
  return track;
}

}  // namespace owval::kinematics
