#pragma once
// The worm's skeleton in its body plane, per frame, head first, in millimetres: what kinematics
// measure, what WCON stores. From a trajectory it is Sibernetic's midline (midline.hpp) in the
// (z, x) plane: skeleton x = simulation z, skeleton y = simulation x (the worm_motion_log swap).
#include <array>
#include <cstddef>
#include <functional>
#include <vector>

#include "owval/trajectory/frame_source.hpp"
#include "owval/trajectory/trajectory.hpp"

namespace owval::kinematics {

using Point2 = std::array<double, 2>;  // (x, y) in mm
using Skeleton = std::vector<Point2>;

struct SkeletonSeries {
  std::vector<double> time_s;       // increasing
  std::vector<Skeleton> skeletons;  // one per time; each head first
};

// Number of points of the normalised skeleton (Yemini et al. 2013; open-worm-analysis-toolbox).
constexpr int kNormalisedPoints = 49;

// The non-empty midline bins of every frame, head (bin 51) first, as body-plane points.
// Throws InputError when the trajectory is not a worm (see IsWorm).
SkeletonSeries SkeletonsFromTrajectory(const Trajectory& trajectory);
// The same, read frame by frame (memory: the skeletons, not the particles of every frame).
SkeletonSeries SkeletonsFromFrames(FrameSource& frames);
// Each frame's time and skeleton in order, read one frame at a time (memory: one frame), for an
// analysis that streams. Throws InputError, as SkeletonsFromTrajectory, when it is not a worm.
void ForEachFrameSkeleton(FrameSource& frames,
                          const std::function<void(double time_s, const Skeleton&)>& observe);
// One frame's skeleton, as SkeletonsFromTrajectory gives it (for frames read one at a time).
Skeleton SkeletonAt(const Trajectory& trajectory, std::size_t frame);

// `points` evenly spaced along the arc length of the polyline, first and last points kept.
Skeleton ResampleByArcLength(const Skeleton& skeleton, int points = kNormalisedPoints);

double ArcLength(const Skeleton& skeleton);

}  // namespace owval::kinematics
