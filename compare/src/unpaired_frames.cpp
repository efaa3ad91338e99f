#include "unpaired_frames.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace owval::compare::internal {

void PeakSpeed::Observe(const FrameRef& frame, std::size_t frame_index, double time_s) {
  const bool first = last_.empty();
  if (first) last_.resize(3 * members_.size());
  const double interval_s = time_s - last_time_s_;
  const bool measured = !first && interval_s > 0;
  if (measured) ++intervals_, duration_s_ += interval_s;
  for (std::size_t k = 0; k < members_.size(); ++k) {
    const float* y = frame.trajectory.position(frame.frame, members_[k]);
    float* was = &last_[3 * k];
    if (measured) {
      const double d =
          std::hypot(double(y[0]) - was[0], double(y[1]) - was[1], double(y[2]) - was[2]);
      const double speed = std::isfinite(d) ? d / interval_s : INFINITY;
      if (speed > speed_cu_s_)
        speed_cu_s_ = speed, particle_ = members_[k], from_frame_ = last_frame_,
        to_frame_ = frame_index;
    }
    was[0] = y[0], was[1] = y[1], was[2] = y[2];
  }
  last_time_s_ = time_s, last_frame_ = frame_index;
}

void Excursions::ObserveUnpaired(const FrameRef& frame) {
  if (pair_.empty()) return;  // before the first pair: outside the common window
  if (pending_frames_++ == 0) {
    lo_.assign(3 * members_.size(), std::numeric_limits<float>::infinity());
    hi_.assign(3 * members_.size(), -std::numeric_limits<float>::infinity());
  }
  for (std::size_t k = 0; k < members_.size(); ++k) {
    const float* y = frame.trajectory.position(frame.frame, members_[k]);
    for (int a = 0; a < 3; ++a) {
      float &lo = lo_[3 * k + a], &hi = hi_[3 * k + a];
      if (!std::isfinite(y[a])) {  // a NaN is no position: as far out as can be
        lo = -std::numeric_limits<float>::infinity(), hi = -lo;
        continue;
      }
      lo = std::min(lo, y[a]), hi = std::max(hi, y[a]);
    }
  }
}

void Excursions::ObservePaired(const FrameRef& frame, std::size_t frame_index, double time_s) {
  const bool first = pair_.empty();
  if (first) pair_.resize(3 * members_.size());
  const double interval_s = time_s - pair_time_s_;
  const bool measured = !first && pending_frames_ > 0 && interval_s > 0;
  if (measured) unpaired_frames_ += pending_frames_;
  for (std::size_t k = 0; k < members_.size(); ++k) {
    const float* y = frame.trajectory.position(frame.frame, members_[k]);
    float* was = &pair_[3 * k];
    if (measured) {
      double excess = 0;
      for (int a = 0; a < 3; ++a) {
        const double top = std::max(double(was[a]), double(y[a]));
        const double bottom = std::min(double(was[a]), double(y[a]));
        excess = std::max({excess, double(hi_[3 * k + a]) - top, bottom - lo_[3 * k + a]});
        if (!std::isfinite(y[a]) || !std::isfinite(was[a])) excess = INFINITY;
      }
      if (excess / interval_s > speed_cu_s_)
        speed_cu_s_ = excess / interval_s, excursion_cu_ = excess, particle_ = members_[k],
        from_frame_ = pair_frame_, to_frame_ = frame_index;
    }
    was[0] = y[0], was[1] = y[1], was[2] = y[2];
  }
  pending_frames_ = 0;
  pair_time_s_ = time_s, pair_frame_ = frame_index;
}

}  // namespace owval::compare::internal
