#pragma once
// The mean signed speed of the head, midbody and tail centroids (kinematics.hpp: the toolbox's
// windows, Yemini et al. 2013), computed as frames arrive. A frame's window opens at it (frame
// i) and closes at the first frame j with t_j >= t_i + w; the speed is the centroid's
// displacement from i to j over t_j - t_i, signed by the tail-to-head direction at frame
// (i + j) / 2. Each window is summed when its closing frame arrives, in the order of i, so the
// means are those of the whole-series loop bit for bit; a frame is dropped once no open window
// needs it (memory: the frames of the longest window, not of the run).
#include <array>
#include <cstddef>
#include <deque>
#include <optional>

#include "owval/kinematics/skeleton.hpp"

namespace owval::kinematics::internal {

// What the speeds need of a frame: its time and its parts' centroids (mm) on the 49-point
// skeleton.
struct PartCentroids {
  double time_s = 0;
  Point2 head, midbody, tail;
};

enum class BodyPart { kHead, kMidbody, kTail };

class SpeedWindows {
 public:
  SpeedWindows(double head_tail_window_s, double midbody_window_s);
  void Observe(const PartCentroids& frame);
  // Mean over the windows closed so far; empty when none closed.
  std::optional<double> MeanSpeed(BodyPart part) const;
  std::size_t held_frames() const { return held_.size(); }

 private:
  struct Window {
    BodyPart part;
    double width_s;
    std::size_t open = 0, close = 0;  // frame indices i and j of the first window not summed
    double sum_mm_s = 0;
    std::size_t closed = 0;
  };
  void Close(Window* w);
  void DropUnneeded();
  const PartCentroids& At(std::size_t frame) const { return held_[frame - first_held_]; }
  std::size_t observed() const { return first_held_ + held_.size(); }

  std::array<Window, 3> windows_;
  std::deque<PartCentroids> held_;
  std::size_t first_held_ = 0;  // frame index of held_.front()
};

}  // namespace owval::kinematics::internal
