#pragma once
// The uniform grid the pair gates search a frame with (closest_approach, held_pair,
// liquid_packing): cells as wide as the search radius, so a particle's neighbours lie in the 27
// cells around its own (S. Green, "Particle Simulation using CUDA", NVIDIA CUDA SDK, 2010: the
// same uniform grid, its particles sorted by cell). Only the particles near the query particles are
// binned (the walls' thousands far from them never are), sorted by cell, each (x, y) column of
// cells found by a hash lookup and its z range by a binary search within the column.
//
// The visits come in one fixed order (query particles in their given order; for each, the
// columns dx = -1..1, dy = -1..1, within a column the bins in their sorted order): the gates'
// sums and their first-found ties depend on it, and `owval compare --json` prints them at full
// precision. What is cached (each cell's nine column ranges, computed once for every query
// particle in it), templated (the visitor, called ~10^6 times a frame on test_energy), packed
// (the sort's key), skipped (cells beyond the radius) and batched (a cell's distances computed
// together, without a branch: VisitBatch) leaves that order as it was
// (docs/benchmarks.md, "pair search as one grid type").
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "owval/trajectory/frame_source.hpp"

namespace owval::compare::internal {

// A position the gates can measure: none of its coordinates NaN or infinite.
inline bool Finite(const float* x) {
  return std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]);
}

class NeighbourGrid {
 public:
  // Bins the finite particles of `frame` that may lie within `radius_cu` of a finite particle of
  // `centres`, in cells of `radius_cu`. Nothing is binned when `radius_cu` is not positive.
  // Keeps a reference to `frame.trajectory`, which must outlive the grid.
  NeighbourGrid(const FrameRef& frame, const std::vector<std::size_t>& centres, double radius_cu);

  // Calls `visit(centre, other, distance_cu)` for every finite particle within `radius_cu` of
  // each finite particle of `centres` (the grid's own), except where `skip(centre, other)`
  // (asked before the distance is computed: pairs met twice are skipped once at no cost).
  template <typename Skip, typename Visit>
  void VisitNeighbours(const std::vector<std::size_t>& centres, const Skip& skip,
                       const Visit& visit);

 private:
  using Cell = std::array<std::int64_t, 3>;
  // A binned particle: its position, read in cell order without a cache miss a candidate
  // (test_energy's 30,000 liquid particles lie far apart in the frame's array).
  struct Slot {
    float x[3];
    std::uint32_t particle;
  };
  struct Run {  // the slots of one cell: [begin, the next run's begin)
    Cell cell;
    std::uint32_t begin;
    std::uint32_t column;  // its index in columns_
  };
  struct Column {  // the runs of one (x, y) column, sorted by z: [first_run, end_run)
    std::int64_t x, y;
    std::uint32_t first_run, end_run;
  };
  // The slots of one column's cells z - 1, z and z + 1 (one stretch in a column sorted by z):
  // [bound[0], bound[1]), [bound[1], bound[2]) and [bound[2], bound[3]).
  struct Stretch {
    std::uint32_t bound[4];
  };
  struct Neighbourhood {  // of one cell: the columns dx = -1..1, dy = -1..1, three cells each
    Cell cell;
    std::array<Stretch, 9> columns;
  };
  using Around = std::array<std::uint32_t, 9>;  // the same columns' indices, kNone: empty
  static constexpr std::uint32_t kNone = 0xFFFFFFFFu;
  static constexpr double kSlack = 1e-9;
  static constexpr std::uint32_t kBatch = 64;  // slots a batch: the candidates on the stack

  template <typename Skip, typename Visit>
  void VisitBatch(std::size_t i, const float* x, std::uint32_t begin, std::uint32_t end,
                  double radius_squared, const Skip& skip, const Visit& visit) const;

  void IndexColumns();
  std::uint32_t FindColumn(std::int64_t x, std::int64_t y) const;
  Stretch CellsAround(std::uint32_t column, std::int64_t z) const;
  Neighbourhood NeighbourhoodOfCell(const Cell& c, std::uint32_t column);
  Around ColumnsAround(std::int64_t x, std::int64_t y) const;
  const Around& ColumnsAround(std::uint32_t column);
  const Neighbourhood& NeighbourhoodOf(std::size_t centre, const float* x);

  const Trajectory& trajectory_;
  std::size_t frame_;
  double radius_cu_;
  std::vector<Slot> slots_;
  std::vector<Run> runs_;            // in slot order, then one whose begin is slots_.size()
  std::vector<std::int64_t> run_z_;  // each run's cell's z: a column's, searched, in a cache line
  std::vector<Column> columns_;      // in run order
  std::vector<std::uint32_t> column_table_;     // columns_' indices by (x, y), open addressing
  std::vector<std::uint32_t> run_of_particle_;  // kNone: not binned
  // Computed when first asked, each column's neighbours and each cell's stretches: a query
  // particle shares them with the others in its column or cell (test_energy's liquid column
  // holds ~30 particles, a cell of h ~8).
  std::vector<Around> columns_around_;
  std::vector<std::uint8_t> columns_around_known_;
  std::vector<std::uint32_t> neighbourhood_of_run_;  // kNone: not yet computed
  std::vector<Neighbourhood> neighbourhoods_;
  Neighbourhood scratch_{};  // of a centre outside every run (never, for a finite centre)
};

template <typename Skip, typename Visit>
void NeighbourGrid::VisitNeighbours(const std::vector<std::size_t>& centres, const Skip& skip,
                                    const Visit& visit) {
  if (slots_.empty()) return;
  const double radius_squared = radius_cu_ * radius_cu_;
  // A cell is searched unless none of its particles can pass the distance test below: its box
  // lies farther than the radius. Its box from its index: a particle y in cell k - 1 has
  // y < k * cell, one in cell k + 1 y >= (k + 1) * cell up to y's rounding; the slack (1e-9 of
  // the coordinates) covers that rounding and the test's own, some 1e-16 of them, so a skipped
  // particle would never have been visited and the visits keep their order.
  const double reach_squared = radius_squared * (1 + kSlack);
  for (std::size_t i : centres) {
    const float* x = trajectory_.position(frame_, i);
    if (!Finite(x)) continue;
    const Neighbourhood& n = NeighbourhoodOf(i, x);
    double gap_squared[3][3];  // axis, offset -1, 0, +1: the nearest a cell there can be
    for (int a = 0; a < 3; ++a) {
      const double slack = kSlack * (std::abs(double(x[a])) + radius_cu_);
      const double below = x[a] - double(n.cell[a]) * radius_cu_ - slack;
      const double above = double(n.cell[a] + 1) * radius_cu_ - x[a] - slack;
      gap_squared[a][0] = below > 0 ? below * below : 0;
      gap_squared[a][1] = 0;
      gap_squared[a][2] = above > 0 ? above * above : 0;
    }
    for (int c = 0; c < 9; ++c) {
      const double across = gap_squared[0][c / 3] + gap_squared[1][c % 3];
      if (across > reach_squared) continue;
      const std::uint32_t* bound = n.columns[std::size_t(c)].bound;
      const std::uint32_t first = across + gap_squared[2][0] > reach_squared ? bound[1] : bound[0];
      const std::uint32_t last = across + gap_squared[2][2] > reach_squared ? bound[2] : bound[3];
      for (std::uint32_t s = first; s < last; s += kBatch)
        VisitBatch(i, x, s, std::min(last, s + kBatch), radius_squared, skip, visit);
    }
  }
}

// The slots [begin, end) within the radius of centre i at x, in slot order: the distances first,
// in a loop of their own without a branch, then the slots within the radius gathered without a
// branch (about one candidate in five passes, at random: a branch on it was mispredicted), then
// the skip test and the visit for those alone. `skip` is pure, so asking it after the distance
// test rather than before visits the same pairs; the arithmetic of each distance is unchanged.
template <typename Skip, typename Visit>
void NeighbourGrid::VisitBatch(std::size_t i, const float* x, std::uint32_t begin,
                               std::uint32_t end, double radius_squared, const Skip& skip,
                               const Visit& visit) const {
  const std::uint32_t n = end - begin;
  double squared[kBatch];
  for (std::uint32_t k = 0; k < n; ++k) {
    const Slot& slot = slots_[begin + k];
    const double ex = double(slot.x[0]) - x[0], ey = double(slot.x[1]) - x[1],
                 ez = double(slot.x[2]) - x[2];
    squared[k] = ex * ex + ey * ey + ez * ez;
  }
  std::uint32_t within[kBatch];
  std::uint32_t count = 0;
  for (std::uint32_t k = 0; k < n; ++k) {
    within[count] = k;
    count += squared[k] <= radius_squared ? 1 : 0;
  }
  for (std::uint32_t j = 0; j < count; ++j) {
    const std::uint32_t k = within[j];
    const std::size_t p = slots_[begin + k].particle;
    if (p == i || skip(i, p)) continue;
    visit(i, p, std::sqrt(squared[k]));
  }
}

// Calls `visit(first, second, distance_cu)` once for every pair within `radius_cu` of `frame`
// with at least one particle in `moving` (first < second), leaving out pairs of two boundary
// particles. Positions that are not finite are skipped.
template <typename Visit>
void ForEachPairWithin(const FrameRef& frame, const std::vector<std::size_t>& moving,
                       double radius_cu, const Visit& visit) {
  const Trajectory& t = frame.trajectory;
  NeighbourGrid grid(frame, moving, radius_cu);
  grid.VisitNeighbours(
      moving,
      // A pair of two moving particles is met from both: counted from the lower index.
      [&](std::size_t i, std::size_t p) {
        return p < i && KindOf(t.type[p]) != ParticleKind::kBoundary;
      },
      [&](std::size_t i, std::size_t p, double d) { visit(i < p ? i : p, i < p ? p : i, d); });
}

// Calls `visit(centre, other, distance_cu)` once for every pair within `radius_cu` with at least
// one particle in `centres` (`other` of any kind; a pair of two centres once, `centre` the higher
// index). What a kernel sum at each centre needs, adding each pair's share to both ends.
template <typename Visit>
void ForEachNeighbourWithin(const FrameRef& frame, const std::vector<std::size_t>& centres,
                            double radius_cu, const Visit& visit) {
  std::vector<char> is_centre(frame.trajectory.particle_count(), 0);
  for (std::size_t i : centres) is_centre[i] = 1;
  NeighbourGrid grid(frame, centres, radius_cu);
  // A pair of two centres is met from both: visited from the higher index.
  grid.VisitNeighbours(
      centres, [&](std::size_t i, std::size_t p) { return p > i && is_centre[p]; }, visit);
}

}  // namespace owval::compare::internal
