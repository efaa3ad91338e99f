#pragma once
// The closest approach of two particles in one frame: the smallest distance between a moving
// particle (elastic or liquid) and any other particle. SPH and PBD keep particles apart (the
// pressure or density constraint grows without bound as two approach: Solenthaler & Pajarola
// 2009, Macklin & Mueller 2013), so two particles never coincide in an honest run and come no
// closer than its rarest encounter; a candidate whose pressure fails, or edited to put one
// particle by another, does. Pairs of two boundary particles are left out: walls are built, not
// simulated.
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

}  // namespace owval::compare::internal
