#pragma once
// The closest approach of two particles in one frame: the smallest distance between a moving
// particle (elastic or liquid) and any other particle. SPH and PBD keep particles apart (the
// pressure or density constraint grows without bound as two approach: Solenthaler & Pajarola
// 2009, Macklin & Mueller 2013), so two particles never coincide in an honest run and come no
// closer than its rarest encounter; a candidate whose pressure fails, or edited to put one
// particle by another, does. Pairs of two boundary particles are left out: walls are built, not
// simulated.
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

#include "neighbour_grid.hpp"
#include "owval/trajectory/frame_source.hpp"

namespace owval::compare::internal {

struct ClosestPair {
  double distance_cu = 0;  // infinite when the frame has no pair with a moving particle
  std::size_t first = 0, second = 0;
};

// The pair searches (ForEachPairWithin, ForEachNeighbourWithin) are neighbour_grid.hpp's.

// Finds the closest pair of `frame` by a uniform grid (cells of `cell_cu`, doubled until a pair
// lies within one cell), querying from `moving`, the non-boundary particles. Positions that are
// not finite are skipped (the worst_particle gates see those).
ClosestPair FindClosestPair(const FrameRef& frame, const std::vector<std::size_t>& moving,
                            double cell_cu);

// The closest approach of two particles (one of them moving) over the paired frames, in each
// run (FindClosestPair, above): pressure holds an honest run's particles apart, so a candidate
// whose particles come much closer than the reference's ever do has particles put where the
// physics cannot put them (demo1: a liquid particle on its neighbour's place from
// frame 1 on passed every distance gate, 4.2 cu being less than honest ports' own differences).
struct ClosestApproach {
  ClosestPair reference{INFINITY}, candidate{INFINITY};
  std::size_t reference_frame = 0, candidate_reference_frame = 0;

  // The last frame's closest distances: the next frame's search starts from a cell a little
  // wider (one sort a frame where the scene changes little; it widens itself when not).
  double last_reference_cu = 0, last_candidate_cu = 0;

  static double CellFrom(double last_cu, double fallback_cu) {
    return std::isfinite(last_cu) && last_cu > 0 ? 1.5 * last_cu : fallback_cu;
  }

  // `known`: each run's closest pair within the held pairs' cap (HeldPairs::Observe), searched
  // for here only when there is none (half a demo1 compare was the two searches).
  void Observe(const FrameRef& ref, const FrameRef& cand, const std::vector<std::size_t>& moving,
               double cell_cu, std::size_t reference_frame_index,
               const std::array<ClosestPair, 2>& known) {
    const ClosestPair r = std::isfinite(known[0].distance_cu)
                              ? known[0]
                              : FindClosestPair(ref, moving, CellFrom(last_reference_cu, cell_cu));
    const ClosestPair c = std::isfinite(known[1].distance_cu)
                              ? known[1]
                              : FindClosestPair(cand, moving, CellFrom(last_candidate_cu, cell_cu));
    last_reference_cu = r.distance_cu, last_candidate_cu = c.distance_cu;
    if (r.distance_cu < reference.distance_cu)
      reference = r, reference_frame = reference_frame_index;
    if (c.distance_cu < candidate.distance_cu)
      candidate = c, candidate_reference_frame = reference_frame_index;
  }
};

}  // namespace owval::compare::internal
