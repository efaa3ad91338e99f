#include "owval/kinematics/side_files.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include <zlib.h>

#include "owval/base/errors.hpp"
#include "owval/kinematics/midline.hpp"

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

// The first disagreement in sizes or times, or "" when they agree.
std::string SizeOrTimeMismatch(const WormTrack& track, const SkeletonSeries& traj) {
  if (track.time_s.size() != traj.time_s.size())
    return std::to_string(track.time_s.size()) + " time points, the trajectory " +
           std::to_string(traj.time_s.size()) + " frames";
  const double allowed_s = kTimeTolerance * MeanInterval_s(traj.time_s);
  for (std::size_t i = 0; i < traj.time_s.size(); ++i) {
    if (std::abs(track.time_s[i] - traj.time_s[i]) > allowed_s)
      return "time point " + std::to_string(i) +
             Format(" at t %.9g s, the trajectory's frame at %.9g s", track.time_s[i],
                    traj.time_s[i]);
    if (track.x_mm[i].size() != traj.skeletons[i].size())
      return "time point " + std::to_string(i) + ": " + std::to_string(track.x_mm[i].size()) +
             " skeleton points, the trajectory " + std::to_string(traj.skeletons[i].size());
  }
  return "";
}

// The file's text; gzopen reads plain files as they are (Sibernetic's logs are kept .gz).
std::string ReadMaybeGzipped(const std::filesystem::path& path) {
  gzFile file = gzopen(path.c_str(), "rb");
  if (!file) throw InputError(path.string(), 0, "cannot open");
  std::string text;
  char buffer[1 << 16];
  int n = 0;
  while ((n = gzread(file, buffer, sizeof buffer)) > 0) text.append(buffer, std::size_t(n));
  const bool failed = n < 0;
  gzclose(file);
  if (failed) throw InputError(path.string(), 0, "corrupt gzip data");
  return text;
}

}  // namespace

TrackAgreement CompareWithTrajectory(const WormTrack& track, const SkeletonSeries& traj) {
  TrackAgreement a;
  const std::string mismatch = SizeOrTimeMismatch(track, traj);
  if (!mismatch.empty()) {
    a.worst_fraction_of_allowance = INFINITY;
    a.detail = mismatch;
    return a;
  }
  std::size_t worst_time = 0, worst_point = 0, failing_times = 0;
  for (std::size_t i = 0; i < traj.time_s.size(); ++i) {
    bool failing = false;
    for (std::size_t k = 0; k < traj.skeletons[i].size(); ++k) {
      const Point2& p = traj.skeletons[i][k];
      const double fraction = std::max(std::abs(track.x_mm[i][k] - p[0]) / Allowance_mm(p[0]),
                                       std::abs(track.y_mm[i][k] - p[1]) / Allowance_mm(p[1]));
      failing = failing || !(fraction <= 1);
      if (fraction > a.worst_fraction_of_allowance || std::isnan(fraction)) {
        a.worst_fraction_of_allowance = std::isnan(fraction) ? INFINITY : fraction;
        worst_time = i, worst_point = k;
      }
    }
    failing_times += failing;
  }
  a.agrees = failing_times == 0;
  const std::size_t i = worst_time, k = worst_point;
  a.detail = std::to_string(traj.time_s.size()) + " time points; " + std::to_string(failing_times) +
             " disagree with the trajectory's skeleton; worst" +
             Format(" %.3g of its allowance", a.worst_fraction_of_allowance);
  if (!traj.time_s.empty() && !traj.skeletons[i].empty())
    a.detail += Format(" at t %.6g s, point ", traj.time_s[i]) + std::to_string(k) +
                Format(": (%.7g, %.7g) mm, the trajectory (%.7g, %.7g) mm", track.x_mm[i][k],
                       track.y_mm[i][k], traj.skeletons[i][k][0], traj.skeletons[i][k][1]);
  return a;
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

}  // namespace

TrackAgreement CompareWithTrajectory(OmeZarrReader& store, FrameSource& traj) {
  TrackAgreement a;
  a.detail = StoreHeaderMismatch(store, traj);
  if (!a.detail.empty()) {
    a.worst_fraction_of_allowance = INFINITY;
    return a;
  }
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
  std::istringstream in(ReadMaybeGzipped(path));
  WormTrack track;
  std::string line;
  for (std::size_t number = 1; std::getline(in, line); ++number) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;  // a blank line
    std::istringstream fields(line);
    double t_s = 0;
    std::string label;
    std::vector<double> block[3];
    // Every field is checked: a blank or cut line has no bins, which the loop below would index.
    const auto malformed = [&] {
      return InputError(path.string(), number,
                        "expected t, then X:, Y:, Z: each with 99 bin means (mm)");
    };
    if (!(fields >> t_s) || !std::isfinite(t_s)) throw malformed();
    for (int b = 0; b < 3; ++b) {
      if (!(fields >> label) || label != std::string(1, char('X' + b)) + ":") throw malformed();
      for (int k = 0; k < kMidlineBins; ++k) {
        double mean_mm = 0;
        if (!(fields >> mean_mm)) throw malformed();
        block[b].push_back(mean_mm);
      }
    }
    track.time_s.push_back(t_s);
    track.x_mm.emplace_back();
    track.y_mm.emplace_back();
    for (int k = 0; k < kMidlineBins; ++k) {
      if (block[0][k] == 0 && block[1][k] == 0 && block[2][k] == 0) continue;  // empty bin
      track.x_mm.back().push_back(static_cast<float>(block[0][k]));            // mean z
      track.y_mm.back().push_back(static_cast<float>(block[1][k]));            // mean x
    }
  }
  return track;
}

}  // namespace owval::kinematics
