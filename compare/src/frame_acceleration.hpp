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
#include "stencil_excess.hpp"

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

// How hard each run pushes its moving particles between paired frames (FrameAcceleration, above),
// per kind (elastic, liquid): each summary's mean over the stencils both runs complete (three
// paired frames evenly spaced in time), so both are measured at the same instants and intervals
// whatever their own log steps; and each stencil's two medians (acceleration.worst_stencil).
struct AccelerationReduction {
  // A second difference of three prints of 6 significant digits, as a fraction of the box's
  // largest extent: 4 x 5e-6, rounded up. Below it a reference's particles barely move.
  static constexpr double kPrintedSecondDifference = 2e-5;
  struct Kind {
    Kind(const char* kind_name, const std::vector<std::size_t>& members)
        : name(kind_name), runs{FrameAcceleration(members), FrameAcceleration(members)} {}
    const char* name;
    FrameAcceleration runs[2];  // reference, candidate
    std::size_t stencils = 0;
    double median_sum[2] = {0, 0}, upper_quartile_sum[2] = {0, 0};  // cu/s^2
    double inverse_interval_squared_sum = 0;                        // 1/s^2, for the floor
    // Each stencil's two medians (reference, candidate) against the other run's nearby, for
    // acceleration.worst_stencil: a window of stencils and the pairs that can still be worst.
    StencilExcesses excesses;
    // Three prints' rounding over the stencils' mean dt^2 (cu/s^2): what a reference at rest
    // measures, for the box's largest extent `box_scale_cu`.
    double PrintedFloor(double box_scale_cu) const {
      return kPrintedSecondDifference * box_scale_cu * inverse_interval_squared_sum /
             double(stencils);
    }
  };
  std::vector<Kind> kinds;
  std::size_t previous_frame = 0;  // the reference frame of the pair observed before

  // The pair at `reference_frame`, at `time_s`: the last frame of a stencil.
  void Observe(const FrameRef& ref, const FrameRef& cand, double time_s,
               std::size_t reference_frame) {
    const std::size_t middle = previous_frame;
    previous_frame = reference_frame;
    for (Kind& k : kinds) {
      const auto r = k.runs[0].Observe(ref, time_s), c = k.runs[1].Observe(cand, time_s);
      if (!r || !c) continue;
      ++k.stencils;
      k.median_sum[0] += r->median, k.median_sum[1] += c->median;
      k.upper_quartile_sum[0] += r->upper_quartile, k.upper_quartile_sum[1] += c->upper_quartile;
      k.inverse_interval_squared_sum += 1 / (r->interval_s * r->interval_s);
      k.excesses.Push(middle, r->median, c->median);
    }
  }
};

}  // namespace owval::compare::internal
