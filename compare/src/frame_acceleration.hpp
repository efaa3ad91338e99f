#pragma once
// How hard the moving particles are pushed between frames, from positions alone: at three
// frames evenly spaced by dt, each particle's second difference |x(t+dt) - 2 x(t) + x(t-dt)| / dt^2
// is its mean acceleration over the two intervals (cu/s^2; the velocity change from one interval
// to the next, over dt). Per stencil it is summarised over a kind's particles (elastic, liquid)
// by the median and the upper quartile, as liquid_packing.hpp summarises the packing.
//
// Why it is a physical invariant: the forces (pressure, elasticity, viscosity, gravity, the
// walls) set the accelerations' distribution, and two runs of the same physics whose chaos has
// diverged still draw their accelerations from it, as they keep the same packing. Noise added
// to each frame (a jittering candidate) adds to every second difference and raises the median
// at once (demo1's elastic median doubles at 0.05 cu of noise, a thirtieth of r0), and a
// time-filtered copy of a run (a moving average over three frames) lowers it by half, while
// both move each particle by far less than the motion gates admit.
#include <cstddef>
#include <optional>
#include <vector>

#include "owval/trajectory/frame_source.hpp"

namespace owval::compare::internal {

struct AccelerationSummary {
  double median = 0;          // over the kind's particles, of |second difference| / dt^2, cu/s^2
  double upper_quartile = 0;  // the same, 75th percentile
  double interval_s = 0;      // dt, the stencil's frame interval
};

// One run's stencil of the last two frames seen, for the particles `members`.
class FrameAcceleration {
 public:
  explicit FrameAcceleration(std::vector<std::size_t> members) : members_(std::move(members)) {}

  // `frame` at `time_s` (times increasing). Returns the summary of the stencil it completes: the
  // two frames before it, spaced as it is from the last (within 1% of the interval: rounding);
  // none before the third frame, after an uneven interval, or when no member is finite.
  std::optional<AccelerationSummary> Observe(const FrameRef& frame, double time_s);

 private:
  std::vector<std::size_t> members_;
  std::vector<float> positions_[2];  // the frame before last ([0]) and the last ([1]), xyz each
  double times_s_[2] = {0, 0};
  int seen_ = 0;  // frames seen, up to 2
};

}  // namespace owval::compare::internal
