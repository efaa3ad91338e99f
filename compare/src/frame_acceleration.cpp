#include "frame_acceleration.hpp"

#include <cmath>

#include "neighbour_grid.hpp"
#include "quantile.hpp"

namespace owval::compare::internal {

std::optional<AccelerationSummary> FrameAcceleration::Observe(const FrameRef& frame,
                                                              double time_s) {
  const Trajectory& t = frame.trajectory;
  std::vector<float> now(3 * members_.size());
  for (std::size_t k = 0; k < members_.size(); ++k) {
    const float* x = t.position(frame.frame, members_[k]);
    for (int a = 0; a < 3; ++a) now[3 * k + a] = x[a];
  }
  std::optional<AccelerationSummary> out;
  const double dt = time_s - times_s_[1];
  // Evenly spaced to 1% of the interval (PairFramesByTime's rounding), or no stencil: a second
  // difference over uneven intervals mixes velocity into it.
  if (seen_ == 2 && dt > 0 && std::abs(dt - (times_s_[1] - times_s_[0])) <= 0.01 * dt) {
    std::vector<double> accelerations;
    accelerations.reserve(members_.size());
    for (std::size_t k = 0; k < members_.size(); ++k) {
      const float* a = &positions_[0][3 * k];
      const float* b = &positions_[1][3 * k];
      const float* c = &now[3 * k];
      if (!Finite(a) || !Finite(b) || !Finite(c)) continue;
      const double d[3] = {double(c[0]) - 2.0 * b[0] + a[0], double(c[1]) - 2.0 * b[1] + a[1],
                           double(c[2]) - 2.0 * b[2] + a[2]};
      accelerations.push_back(std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) / (dt * dt));
    }
    if (!accelerations.empty()) {
      AccelerationSummary s;
      s.interval_s = dt;
      s.upper_quartile = Quantile(accelerations, 0.75);
      s.median = Quantile(accelerations, 0.5);
      out = s;
    }
  }
  positions_[0].swap(positions_[1]);
  positions_[1].swap(now);
  times_s_[0] = times_s_[1], times_s_[1] = time_s;
  seen_ = seen_ < 2 ? seen_ + 1 : 2;
  return out;
}

}  // namespace owval::compare::internal
