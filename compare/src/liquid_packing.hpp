#pragma once
// How tightly the liquid is packed, from positions alone: at each liquid particle the SPH kernel
// sum over every particle (liquid, elastic and boundary, itself included) within the support h,
// with Muller et al. 2003's Wpoly6 (M. Muller, D. Charypar, M. Gross, "Particle-based fluid
// simulation for interactive applications", SCA 2003), the kernel Sibernetic's density uses
// (sphFluid.cl, pcisph_computeDensity). Divided by Wpoly6(0), it is the particle's density over
// the density of a particle alone: mass and the kernel's constant cancel, so a trajectory of
// positions measures it, whatever the candidate's own density column claims (Sibernetic writes
// none). Per frame it is summarised over the liquid particles by two robust order statistics:
// the median and the upper quartile (the bulk; the free surface's particles, short of
// neighbours, fill the lower quartile).
#include <cmath>
#include <cstddef>
#include <vector>

#include "owval/trajectory/frame_source.hpp"

namespace owval::compare::internal {

struct PackingSummary {
  double median = 0;          // over the liquid particles, of the kernel sum / Wpoly6(0)
  double upper_quartile = 0;  // the same, 75th percentile
};

// The kernel sums of `liquid` in `frame` with support `support_cu`, summarised. Particles whose
// position is not finite are left out of the summary (and add nothing); none left: zeros.
PackingSummary MeasurePacking(const FrameRef& frame, const std::vector<std::size_t>& liquid,
                              double support_cu);

// How tightly each run's liquid is packed (MeasurePacking, above), per paired frame, reduced to
// the mean over the paired frames of each summary and the frame where the two runs differ most.
struct PackingReduction {
  double support_cu = 0;  // twice the reference's median spacing at its first paired frame
  std::size_t frames = 0;
  double median_sum[2] = {0, 0}, upper_quartile_sum[2] = {0, 0};  // reference, candidate
  // The paired frame whose upper quartiles differ most, relatively, and both runs' values there.
  double worst_frame_gap = -1;
  std::size_t worst_frame = 0;
  PackingSummary worst[2];

  void Observe(const PackingSummary& ref, const PackingSummary& cand, std::size_t reference_frame) {
    ++frames;
    median_sum[0] += ref.median, median_sum[1] += cand.median;
    upper_quartile_sum[0] += ref.upper_quartile, upper_quartile_sum[1] += cand.upper_quartile;
    const double gap = std::abs(cand.upper_quartile / ref.upper_quartile - 1);
    if (!(gap <= worst_frame_gap))
      worst_frame_gap = gap, worst_frame = reference_frame, worst[0] = ref, worst[1] = cand;
  }
};

}  // namespace owval::compare::internal
