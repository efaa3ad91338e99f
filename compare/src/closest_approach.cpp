#include "closest_approach.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

namespace owval::compare::internal {
namespace {

using Cell = std::array<std::int64_t, 3>;

struct Binned {
  Cell cell;
  std::size_t particle;
  bool operator<(const Binned& other) const { return cell < other.cell; }
};

Cell CellOf(const float* x, double cell_cu) {
  return {std::int64_t(std::floor(x[0] / cell_cu)), std::int64_t(std::floor(x[1] / cell_cu)),
          std::int64_t(std::floor(x[2] / cell_cu))};
}

bool Finite(const float* x) {
  return std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]);
}

// The finite particles within `radius_cu` of the moving particles' bounding box, sorted by cell:
// a pair closer than the radius lies within it on every axis, and the walls' thousands far from
// the moving particles are never binned (the per-frame sort of every particle was 90% of a demo1
// compare).
std::vector<Binned> BinNearMoving(const FrameRef& f, const std::vector<std::size_t>& moving,
                                  double radius_cu) {
  const Trajectory& t = f.trajectory;
  double low[3] = {INFINITY, INFINITY, INFINITY}, high[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (std::size_t i : moving) {
    const float* x = t.position(f.frame, i);
    if (!Finite(x)) continue;
    for (int a = 0; a < 3; ++a) low[a] = std::min(low[a], x[a] - radius_cu);
    for (int a = 0; a < 3; ++a) high[a] = std::max(high[a], x[a] + radius_cu);
  }
  std::vector<Binned> bins;
  for (std::size_t p = 0; p < t.particle_count(); ++p) {
    const float* x = t.position(f.frame, p);
    if (!Finite(x)) continue;
    bool near = true;
    for (int a = 0; a < 3; ++a) near = near && x[a] >= low[a] && x[a] <= high[a];
    if (near) bins.push_back({CellOf(x, radius_cu), p});
  }
  std::sort(bins.begin(), bins.end());
  return bins;
}

}  // namespace

void ForEachPairWithin(const FrameRef& f, const std::vector<std::size_t>& moving, double radius_cu,
                       const std::function<void(std::size_t, std::size_t, double)>& visit) {
  if (!(radius_cu > 0)) return;
  const Trajectory& t = f.trajectory;
  const std::vector<Binned> bins = BinNearMoving(f, moving, radius_cu);
  const double radius_squared = radius_cu * radius_cu;
  for (std::size_t i : moving) {
    const float* x = t.position(f.frame, i);
    if (!Finite(x)) continue;
    const Cell c = CellOf(x, radius_cu);
    for (std::int64_t dx = -1; dx <= 1; ++dx)
      for (std::int64_t dy = -1; dy <= 1; ++dy)
        for (std::int64_t dz = -1; dz <= 1; ++dz) {
          const Binned key{{c[0] + dx, c[1] + dy, c[2] + dz}, 0};
          const auto [lo, hi] = std::equal_range(bins.begin(), bins.end(), key);
          for (auto it = lo; it != hi; ++it) {
            const std::size_t p = it->particle;
            // A pair of two moving particles is met from both: counted from the lower index.
            if (p == i || (p < i && KindOf(t.type[p]) != ParticleKind::kBoundary)) continue;
            const float* y = t.position(f.frame, p);
            const double ex = double(y[0]) - x[0], ey = double(y[1]) - x[1],
                         ez = double(y[2]) - x[2];
            const double squared = ex * ex + ey * ey + ez * ez;
            if (squared <= radius_squared)
              visit(std::min(i, p), std::max(i, p), std::sqrt(squared));
          }
        }
  }
}

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
