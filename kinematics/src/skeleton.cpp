#include "owval/kinematics/skeleton.hpp"

#include <algorithm>
#include <cmath>

#include "owval/base/errors.hpp"
#include "owval/kinematics/midline.hpp"

namespace owval::kinematics {

SkeletonSeries SkeletonsFromTrajectory(const Trajectory& trajectory) {
  if (!IsWorm(trajectory))
    throw InputError(
        "trajectory has no worm body (no elastic particles with midline codes 2.1xxx)");
  SkeletonSeries series;
  for (std::size_t f = 0; f < trajectory.frame_count(); ++f) {
    series.time_s.push_back(trajectory.time_s[f]);
    series.skeletons.push_back(SkeletonAt(trajectory, f));
  }
  return series;
}

void ForEachFrameSkeleton(FrameSource& frames,
                          const std::function<void(double time_s, const Skeleton&)>& observe) {
  if (!IsWorm(frames.header()))
    throw InputError(
        "trajectory has no worm body (no elastic particles with midline codes 2.1xxx)");
  for (std::size_t f = 0; f < frames.frame_count(); ++f) {
    const FrameRef frame = frames.Frame(f);
    observe(frames.header().time_s[f], SkeletonAt(frame.trajectory, frame.frame));
  }
}

SkeletonSeries SkeletonsFromFrames(FrameSource& frames) {
  SkeletonSeries series;
  ForEachFrameSkeleton(frames, [&](double time_s, const Skeleton& skeleton) {
    series.time_s.push_back(time_s);
    series.skeletons.push_back(skeleton);
  });
  return series;
}

Skeleton SkeletonAt(const Trajectory& trajectory, std::size_t frame) {
  const Midline m = ComputeMidline(trajectory, frame);
  Skeleton s;
  for (int b = 0; b < kMidlineBins; ++b)
    if (m.count[b] > 0) s.push_back({m.z_mm[b], m.x_mm[b]});
  return s;
}

double ArcLength(const Skeleton& s) {
  double length = 0;
  for (std::size_t i = 1; i < s.size(); ++i)
    length += std::hypot(s[i][0] - s[i - 1][0], s[i][1] - s[i - 1][1]);
  return length;
}

Skeleton ResampleByArcLength(const Skeleton& s, int points) {
  if (s.size() < 2 || points < 2) throw InputError("skeleton needs at least 2 points");
  std::vector<double> cumulative(s.size(), 0.0);
  for (std::size_t i = 1; i < s.size(); ++i)
    cumulative[i] = cumulative[i - 1] + std::hypot(s[i][0] - s[i - 1][0], s[i][1] - s[i - 1][1]);
  const double total = cumulative.back();
  Skeleton out(points);
  std::size_t segment = 1;
  for (int k = 0; k < points; ++k) {
    const double at = total * k / (points - 1);
    while (segment + 1 < s.size() && cumulative[segment] < at) ++segment;
    const double span = cumulative[segment] - cumulative[segment - 1];
    const double w = span > 0 ? std::clamp((at - cumulative[segment - 1]) / span, 0.0, 1.0) : 0.0;
    for (int a = 0; a < 2; ++a)
      out[k][a] = s[segment - 1][a] + w * (s[segment][a] - s[segment - 1][a]);
  }
  return out;
}

}  // namespace owval::kinematics
