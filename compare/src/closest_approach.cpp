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

// The closest pair within one cell's width, by the 27 cells around each moving particle; its
// distance is infinite when no pair is that close.
ClosestPair ClosestWithinCell(const FrameRef& f, const std::vector<std::size_t>& moving,
                              double cell_cu) {
  const Trajectory& t = f.trajectory;
  // A pair closer than one cell lies within one cell of the moving particles' bounding box on
  // every axis: only particles there are binned, not the walls' thousands far from them (the
  // per-frame sort of every particle was 90% of a demo1 compare).
  double low[3] = {INFINITY, INFINITY, INFINITY}, high[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (std::size_t i : moving) {
    const float* x = t.position(f.frame, i);
    if (!Finite(x)) continue;
    for (int a = 0; a < 3; ++a) low[a] = std::min(low[a], x[a] - cell_cu);
    for (int a = 0; a < 3; ++a) high[a] = std::max(high[a], x[a] + cell_cu);
  }
  const auto near_moving = [&](const float* x) {
    for (int a = 0; a < 3; ++a)
      if (x[a] < low[a] || x[a] > high[a]) return false;
    return true;
  };
  std::vector<Binned> bins;
  for (std::size_t p = 0; p < t.particle_count(); ++p) {
    const float* x = t.position(f.frame, p);
    if (Finite(x) && near_moving(x)) bins.push_back({CellOf(x, cell_cu), p});
  }
  std::sort(bins.begin(), bins.end());
  ClosestPair best{std::numeric_limits<double>::infinity()};
  double best_squared = cell_cu * cell_cu;
  for (std::size_t i : moving) {
    const float* x = t.position(f.frame, i);
    if (!Finite(x)) continue;
    const Cell c = CellOf(x, cell_cu);
    for (std::int64_t dx = -1; dx <= 1; ++dx)
      for (std::int64_t dy = -1; dy <= 1; ++dy)
        for (std::int64_t dz = -1; dz <= 1; ++dz) {
          const Binned key{{c[0] + dx, c[1] + dy, c[2] + dz}, 0};
          const auto [lo, hi] = std::equal_range(bins.begin(), bins.end(), key);
          for (auto it = lo; it != hi; ++it) {
            if (it->particle == i) continue;
            const float* y = t.position(f.frame, it->particle);
            const double ex = double(y[0]) - x[0], ey = double(y[1]) - x[1],
                         ez = double(y[2]) - x[2];
            const double squared = ex * ex + ey * ey + ez * ez;
            if (squared < best_squared) {
              best_squared = squared;
              best = {std::sqrt(squared), std::min(i, it->particle), std::max(i, it->particle)};
            }
          }
        }
  }
  return best;
}

}  // namespace

ClosestPair FindClosestPair(const FrameRef& frame, const std::vector<std::size_t>& moving,
                            double cell_cu) {
  if (!(cell_cu > 0)) cell_cu = 1;
  // A pair closer than the cell's width is found by its 27 cells; none found: widen. Forty
  // doublings reach any finite box.
  for (int widen = 0; widen < 40; ++widen, cell_cu *= 2) {
    const ClosestPair pair = ClosestWithinCell(frame, moving, cell_cu);
    if (std::isfinite(pair.distance_cu)) return pair;
  }
  return {std::numeric_limits<double>::infinity()};
}

}  // namespace owval::compare::internal
