#include "closest_approach.hpp"

#include <cmath>
#include <limits>

namespace owval::compare::internal {

ClosestPair FindClosestPair(const FrameRef& frame, const std::vector<std::size_t>& moving,
                            double cell_cu) {
  if (!(cell_cu > 0)) cell_cu = 1;
  // A pair closer than the cell's width is found by its 27 cells; none found: widen. Forty
  // doublings reach any finite box.
  for (int widen = 0; widen < 40; ++widen, cell_cu *= 2) {
    ClosestPair best{std::numeric_limits<double>::infinity()};
    ForEachPairWithin(frame, moving, cell_cu, [&best](std::size_t a, std::size_t b, double d) {
      if (d < best.distance_cu) best = {d, a, b};
    });
    if (std::isfinite(best.distance_cu)) return best;
  }
  return {std::numeric_limits<double>::infinity()};
}

}  // namespace owval::compare::internal
