#include "liquid_packing.hpp"

#include <algorithm>
#include <cmath>

#include "neighbour_grid.hpp"
#include "quantile.hpp"

namespace owval::compare::internal {

PackingSummary MeasurePacking(const FrameRef& frame, const std::vector<std::size_t>& liquid,
                              double support_cu) {
  const Trajectory& t = frame.trajectory;
  std::vector<double> sum(t.particle_count(), 0.0);
  const double support_squared = support_cu * support_cu;
  // Wpoly6(r) / Wpoly6(0) = (1 - r^2/h^2)^3, each pair's share added to both ends' sums (only
  // the liquid's are read). A centre's visits come together and never name it as `b`, so its sum
  // is carried in a register meanwhile (sum[a] in memory, which sum[b] may alias, was reloaded
  // every pair): the same additions in the same order.
  constexpr std::size_t kNoCentre = ~std::size_t(0);
  std::size_t centre = kNoCentre;
  double centre_sum = 0;
  ForEachNeighbourWithin(frame, liquid, support_cu, [&](std::size_t a, std::size_t b, double d) {
    const double u = 1 - d * d / support_squared;
    const double w = u * u * u;
    if (a != centre) {
      if (centre != kNoCentre) sum[centre] = centre_sum;
      centre = a, centre_sum = sum[a];
    }
    centre_sum += w, sum[b] += w;
  });
  if (centre != kNoCentre) sum[centre] = centre_sum;
  std::vector<double> of_liquid;
  of_liquid.reserve(liquid.size());
  for (std::size_t i : liquid)
    if (Finite(t.position(frame.frame, i))) of_liquid.push_back(1 + sum[i]);  // 1: itself
  if (of_liquid.empty()) return {};
  PackingSummary s;
  s.upper_quartile = Quantile(of_liquid, 0.75);
  s.median = Quantile(of_liquid, 0.5);
  return s;
}

}  // namespace owval::compare::internal
