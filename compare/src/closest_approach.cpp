#include "closest_approach.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>
#include <utility>

namespace owval::compare::internal {
namespace {

using Cell = std::array<std::int64_t, 3>;

struct Binned {
  Cell cell;
  std::size_t particle;
  // Its position, read in cell order without a cache miss a candidate (test_energy's 30,000
  // liquid particles lie far apart in the frame's array).
  float x[3];
  bool operator<(const Binned& other) const { return cell < other.cell; }
};

Cell CellOf(const float* x, double cell_cu) {
  return {std::int64_t(std::floor(x[0] / cell_cu)), std::int64_t(std::floor(x[1] / cell_cu)),
          std::int64_t(std::floor(x[2] / cell_cu))};
}

bool Finite(const float* x) {
  return std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]);
}

// Which blocks of the query particles' bounding box (padded by the radius) hold a query
// particle or touch one that does: a particle within the radius of a query particle lies in such
// a block, since blocks are at least the radius wide. demo1's liquid spreads over the whole
// floor, whose bounding box holds thousands of wall particles that no query particle is near.
class NearBlocks {
 public:
  NearBlocks(const double low[3], const double high[3], double radius_cu) {
    for (int a = 0; a < 3; ++a) {
      low_[a] = low[a];
      block_cu_[a] = std::max(radius_cu, (high[a] - low[a]) / kBlocksPerSide);
      sides_[a] = std::int64_t((high[a] - low[a]) / block_cu_[a]) + 1;
    }
    near_.assign(std::size_t(sides_[0] * sides_[1] * sides_[2]), 0);
  }
  void MarkAround(const float* x) {
    std::int64_t b[3];
    for (int a = 0; a < 3; ++a) b[a] = BlockOf(x, a);
    for (std::int64_t i = std::max<std::int64_t>(b[0] - 1, 0);
         i <= std::min(b[0] + 1, sides_[0] - 1); ++i)
      for (std::int64_t j = std::max<std::int64_t>(b[1] - 1, 0);
           j <= std::min(b[1] + 1, sides_[1] - 1); ++j)
        for (std::int64_t k = std::max<std::int64_t>(b[2] - 1, 0);
             k <= std::min(b[2] + 1, sides_[2] - 1); ++k)
          near_[std::size_t((i * sides_[1] + j) * sides_[2] + k)] = 1;
  }
  // `x` inside the padded bounding box.
  bool Near(const float* x) const {
    return near_[std::size_t((BlockOf(x, 0) * sides_[1] + BlockOf(x, 1)) * sides_[2] +
                             BlockOf(x, 2))] != 0;
  }

 private:
  static constexpr double kBlocksPerSide = 32;  // 35^3 flags at most, cleared every call
  std::int64_t BlockOf(const float* x, int a) const {
    return std::clamp<std::int64_t>(std::int64_t((x[a] - low_[a]) / block_cu_[a]), 0,
                                    sides_[a] - 1);
  }
  double low_[3], block_cu_[3];
  std::int64_t sides_[3];
  std::vector<std::uint8_t> near_;
};

// The finite particles near the moving particles (within `radius_cu` of their bounding box, and
// in a block by one of them: NearBlocks), sorted by cell: the walls' thousands far from the
// moving particles are never binned (the per-frame sort of every particle was 90% of a demo1
// compare; of the bounding box's, half a compare with the liquid_packing gate's wider search).
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
  if (!(low[0] <= high[0])) return bins;  // no finite moving particle
  NearBlocks blocks(low, high, radius_cu);
  for (std::size_t i : moving)
    if (Finite(t.position(f.frame, i))) blocks.MarkAround(t.position(f.frame, i));
  for (std::size_t p = 0; p < t.particle_count(); ++p) {
    const float* x = t.position(f.frame, p);
    if (!Finite(x)) continue;
    bool near = true;
    for (int a = 0; a < 3; ++a) near = near && x[a] >= low[a] && x[a] <= high[a];
    if (near && blocks.Near(x)) bins.push_back({CellOf(x, radius_cu), p, {x[0], x[1], x[2]}});
  }
  std::sort(bins.begin(), bins.end());
  return bins;
}

// Where each (x, y) column of cells lies in the bins (sorted by x, y, z, so a column is one run):
// a hash lookup and two binary searches within the column instead of two over every bin for
// each of a query particle's nine columns (most of a compare's time with the
// liquid_packing gate). The runs found are those the binary searches found.
class ColumnIndex {
 public:
  explicit ColumnIndex(const std::vector<Binned>& bins) : bins_(bins) {
    columns_.reserve(bins.size());
    for (std::size_t begin = 0, end = 0; begin < bins.size(); begin = end) {
      end = begin + 1;
      while (end < bins.size() && SameColumn(bins[end].cell, bins[begin].cell)) ++end;
      columns_.emplace(std::pair{bins[begin].cell[0], bins[begin].cell[1]}, Run{begin, end});
    }
  }
  // The bins of column (x, y) whose z lies in [z_low, z_high], as [first, last).
  std::pair<const Binned*, const Binned*> Find(std::int64_t x, std::int64_t y, std::int64_t z_low,
                                               std::int64_t z_high) const {
    const auto it = columns_.find(std::pair{x, y});
    if (it == columns_.end()) return {nullptr, nullptr};
    const Binned* first = bins_.data() + it->second.begin;
    const Binned* last = bins_.data() + it->second.end;
    // A column spans the scene's height: its z range by binary search.
    first = std::partition_point(first, last, [&](const Binned& b) { return b.cell[2] < z_low; });
    return {first, std::partition_point(first, last,
                                        [&](const Binned& b) { return b.cell[2] <= z_high; })};
  }

 private:
  struct Run {
    std::size_t begin, end;
  };
  struct KeyHash {
    std::size_t operator()(const std::pair<std::int64_t, std::int64_t>& k) const {
      return std::hash<std::uint64_t>()(std::uint64_t(k.first) * 0x9E3779B97F4A7C15ull ^
                                        std::uint64_t(k.second));
    }
  };
  static bool SameColumn(const Cell& a, const Cell& b) { return a[0] == b[0] && a[1] == b[1]; }
  const std::vector<Binned>& bins_;
  std::unordered_map<std::pair<std::int64_t, std::int64_t>, Run, KeyHash> columns_;
};

}  // namespace

namespace {

// Calls `visit(centre, other, distance_cu)` for every finite particle within `radius_cu` of each
// finite particle of `centres`, except where `skip(centre, other)` (asked before the distance is
// computed: pairs met twice are skipped once at no cost).
template <typename Skip, typename Visit>
void VisitNeighbours(const FrameRef& f, const std::vector<std::size_t>& centres, double radius_cu,
                     const Skip& skip, const Visit& visit) {
  if (!(radius_cu > 0)) return;
  const Trajectory& t = f.trajectory;
  const std::vector<Binned> bins = BinNearMoving(f, centres, radius_cu);
  const ColumnIndex columns(bins);
  const double radius_squared = radius_cu * radius_cu;
  for (std::size_t i : centres) {
    const float* x = t.position(f.frame, i);
    if (!Finite(x)) continue;
    const Cell c = CellOf(x, radius_cu);
    // Cells sorted by x, y, z: the three cells of one (x, y) column are one range of the bins.
    for (std::int64_t dx = -1; dx <= 1; ++dx)
      for (std::int64_t dy = -1; dy <= 1; ++dy) {
        const auto [lo, hi] = columns.Find(c[0] + dx, c[1] + dy, c[2] - 1, c[2] + 1);
        for (const Binned* it = lo; it != hi; ++it) {
          const std::size_t p = it->particle;
          if (p == i || skip(i, p)) continue;
          const float* y = it->x;
          const double ex = double(y[0]) - x[0], ey = double(y[1]) - x[1], ez = double(y[2]) - x[2];
          const double squared = ex * ex + ey * ey + ez * ez;
          if (squared <= radius_squared) visit(i, p, std::sqrt(squared));
        }
      }
  }
}

}  // namespace

void ForEachPairWithin(const FrameRef& f, const std::vector<std::size_t>& moving, double radius_cu,
                       const std::function<void(std::size_t, std::size_t, double)>& visit) {
  const Trajectory& t = f.trajectory;
  VisitNeighbours(
      f, moving, radius_cu,
      // A pair of two moving particles is met from both: counted from the lower index.
      [&](std::size_t i, std::size_t p) {
        return p < i && KindOf(t.type[p]) != ParticleKind::kBoundary;
      },
      [&](std::size_t i, std::size_t p, double d) { visit(std::min(i, p), std::max(i, p), d); });
}

void ForEachNeighbourWithin(const FrameRef& frame, const std::vector<std::size_t>& centres,
                            double radius_cu,
                            const std::function<void(std::size_t, std::size_t, double)>& visit) {
  std::vector<char> is_centre(frame.trajectory.particle_count(), 0);
  for (std::size_t i : centres) is_centre[i] = 1;
  // A pair of two centres is met from both: visited from the higher index.
  VisitNeighbours(
      frame, centres, radius_cu,
      [&](std::size_t i, std::size_t p) { return p > i && is_centre[p]; }, visit);
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
