#include "speed_windows.hpp"

#include <algorithm>
#include <cmath>

namespace owval::kinematics::internal {
namespace {

const Point2& Of(const PartCentroids& c, BodyPart part) {
  return part == BodyPart::kHead ? c.head : part == BodyPart::kMidbody ? c.midbody : c.tail;
}

}  // namespace

SpeedWindows::SpeedWindows(double head_tail_window_s, double midbody_window_s)
    : windows_{Window{BodyPart::kHead, head_tail_window_s},
               Window{BodyPart::kMidbody, midbody_window_s},
               Window{BodyPart::kTail, head_tail_window_s}} {}

void SpeedWindows::Observe(const PartCentroids& frame) {
  held_.push_back(frame);
  for (Window& w : windows_) Close(&w);
  DropUnneeded();
}

// Every window that the frames observed so far close (a window still open waits for the next).
void SpeedWindows::Close(Window* w) {
  const std::size_t n = observed();
  while (w->open < n) {
    // 1e-9 s: a frame at t_i + w by the log step's arithmetic closes the window.
    while (w->close < n && At(w->close).time_s < At(w->open).time_s + w->width_s - 1e-9) ++w->close;
    if (w->close >= n) return;
    const PartCentroids &i = At(w->open), &j = At(w->close);
    const Point2 a = Of(i, w->part), b = Of(j, w->part);
    const Point2 d{b[0] - a[0], b[1] - a[1]};
    // Forward: along the tail-to-head direction at the middle of the window.
    const PartCentroids& mid = At((w->open + w->close) / 2);
    const double along = d[0] * (mid.head[0] - mid.tail[0]) + d[1] * (mid.head[1] - mid.tail[1]);
    const double speed = std::hypot(d[0], d[1]) / (j.time_s - i.time_s);
    w->sum_mm_s += along < 0 ? -speed : speed;
    ++w->closed;
    ++w->open;
  }
}

// The oldest frame a window still needs: its opening or closing frame (the closing one is the
// earlier only when the times do not increase).
void SpeedWindows::DropUnneeded() {
  std::size_t needed = observed();
  for (const Window& w : windows_) needed = std::min({needed, w.open, w.close});
  while (first_held_ < needed) {
    held_.pop_front();
    ++first_held_;
  }
}

std::optional<double> SpeedWindows::MeanSpeed(BodyPart part) const {
  for (const Window& w : windows_)
    if (w.part == part && w.closed > 0) return w.sum_mm_s / w.closed;
  return std::nullopt;
}

}  // namespace owval::kinematics::internal
