#include "neighbour_grid.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace owval::compare::internal {
namespace {

using Cell = std::array<std::int64_t, 3>;

// A particle as binned, in the order the grid visits: sorted by cell with std::sort, whose order
// within a cell (it is not stable) the visits follow. std::sort's permutation depends only on the
// outcomes of its comparisons, so sorting a cell packed into one integer (order kept: Packed)
// gives the permutation of sorting the cells themselves, in a third of the bytes moved.
struct Binned {
  Cell cell;
  std::size_t particle;
  bool operator<(const Binned& other) const { return cell < other.cell; }
};

Cell CellOf(const float* x, double cell_cu) {
  return {std::int64_t(std::floor(x[0] / cell_cu)), std::int64_t(std::floor(x[1] / cell_cu)),
          std::int64_t(std::floor(x[2] / cell_cu))};
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

// Cells packed into 64 bits, 21 bits an axis counted from the lowest cell, when the cells span
// fewer than 2^21 a side (always, for the gates' radii in a Sibernetic box): x, then y, then z,
// as the cells' own order.
class Packed {
 public:
  Packed(const double low[3], const double high[3], double cell_cu) {
    fits_ = true;
    for (int a = 0; a < 3; ++a) {
      const double first = std::floor(low[a] / cell_cu), last = std::floor(high[a] / cell_cu);
      // False for a NaN too; cells beyond 2^62 (a broken run's far particle) are not packed.
      fits_ = fits_ && last - first < double(kSide) && std::abs(first) < 0x1p62 &&
              std::abs(last) < 0x1p62;
      base_[a] = fits_ ? std::int64_t(first) : 0;
    }
  }
  bool fits() const { return fits_; }
  std::uint64_t Key(const Cell& c) const {
    return std::uint64_t(c[0] - base_[0]) << 42 | std::uint64_t(c[1] - base_[1]) << 21 |
           std::uint64_t(c[2] - base_[2]);
  }
  Cell CellOf(std::uint64_t key) const {
    return {base_[0] + std::int64_t(key >> 42), base_[1] + std::int64_t(key >> 21 & (kSide - 1)),
            base_[2] + std::int64_t(key & (kSide - 1))};
  }

 private:
  static constexpr std::uint64_t kSide = std::uint64_t(1) << 21;
  bool fits_;
  std::int64_t base_[3];
};

struct KeyedParticle {
  std::uint64_t key;
  std::size_t particle;
  bool operator<(const KeyedParticle& other) const { return key < other.key; }
};

// Sorts `bins` (in particle order) by cell as std::sort of Binned would.
void SortByCell(std::vector<Binned>& bins, const Packed& packed) {
  if (!packed.fits()) return std::sort(bins.begin(), bins.end());
  std::vector<KeyedParticle> keyed;
  keyed.reserve(bins.size());
  for (const Binned& b : bins) keyed.push_back({packed.Key(b.cell), b.particle});
  std::sort(keyed.begin(), keyed.end());
  for (std::size_t k = 0; k < keyed.size(); ++k)
    bins[k] = {packed.CellOf(keyed[k].key), keyed[k].particle};
}

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
    if (near && blocks.Near(x)) bins.push_back({CellOf(x, radius_cu), p});
  }
  // Every binned x lies within [low, high], so its cell within theirs.
  SortByCell(bins, Packed(low, high, radius_cu));
  return bins;
}

std::size_t ColumnHash(std::int64_t x, std::int64_t y) {
  std::uint64_t h = std::uint64_t(x) * 0x9E3779B97F4A7C15ull ^ std::uint64_t(y);
  h ^= h >> 29;  // the table's index takes the low bits: mix the high ones in
  h *= 0xBF58476D1CE4E5B9ull;
  return std::size_t(h ^ (h >> 32));
}

}  // namespace

NeighbourGrid::NeighbourGrid(const FrameRef& frame, const std::vector<std::size_t>& centres,
                             double radius_cu)
    : trajectory_(frame.trajectory), frame_(frame.frame), radius_cu_(radius_cu) {
  if (!(radius_cu > 0)) return;
  // Slots and runs are numbered in 32 bits (a quarter of the memory of a size_t in the hot loop).
  if (trajectory_.particle_count() >= kNone)
    throw std::length_error("the pair search takes fewer than 2^32 - 1 particles");
  const std::vector<Binned> bins = BinNearMoving(frame, centres, radius_cu);
  slots_.reserve(bins.size());
  run_of_particle_.assign(trajectory_.particle_count(), kNone);
  for (std::size_t b = 0; b < bins.size(); ++b) {
    if (b == 0 || bins[b].cell != bins[b - 1].cell)
      runs_.push_back({bins[b].cell, std::uint32_t(b), 0});
    run_of_particle_[bins[b].particle] = std::uint32_t(runs_.size() - 1);
    const float* x = trajectory_.position(frame_, bins[b].particle);
    slots_.push_back({{x[0], x[1], x[2]}, std::uint32_t(bins[b].particle)});
  }
  neighbourhood_of_run_.assign(runs_.size(), kNone);
  IndexColumns();
  for (const Run& r : runs_) run_z_.push_back(r.cell[2]);
  runs_.push_back({{}, std::uint32_t(bins.size()), kNone});
}

// Runs are sorted by x, y, z: a column is one stretch of them.
void NeighbourGrid::IndexColumns() {
  for (std::uint32_t begin = 0, end = 0; begin < runs_.size(); begin = end) {
    const Cell& c = runs_[begin].cell;
    end = begin + 1;
    while (end < runs_.size() && runs_[end].cell[0] == c[0] && runs_[end].cell[1] == c[1]) ++end;
    for (std::uint32_t r = begin; r < end; ++r) runs_[r].column = std::uint32_t(columns_.size());
    columns_.push_back({c[0], c[1], begin, end});
  }
  std::size_t size = 16;
  while (size < 2 * columns_.size()) size *= 2;  // at most half full
  column_table_.assign(size, kNone);
  for (std::uint32_t k = 0; k < columns_.size(); ++k) {
    std::size_t slot = ColumnHash(columns_[k].x, columns_[k].y) & (size - 1);
    while (column_table_[slot] != kNone) slot = (slot + 1) & (size - 1);
    column_table_[slot] = k;
  }
  columns_around_.resize(columns_.size());
  columns_around_known_.assign(columns_.size(), 0);
}

std::uint32_t NeighbourGrid::FindColumn(std::int64_t x, std::int64_t y) const {
  const std::size_t mask = column_table_.size() - 1;
  for (std::size_t slot = ColumnHash(x, y) & mask;; slot = (slot + 1) & mask) {
    const std::uint32_t k = column_table_[slot];
    if (k == kNone || (columns_[k].x == x && columns_[k].y == y)) return k;
  }
}

NeighbourGrid::Around NeighbourGrid::ColumnsAround(std::int64_t x, std::int64_t y) const {
  Around around{};
  std::size_t n = 0;
  for (std::int64_t dx = -1; dx <= 1; ++dx)
    for (std::int64_t dy = -1; dy <= 1; ++dy) around[n++] = FindColumn(x + dx, y + dy);
  return around;
}

const NeighbourGrid::Around& NeighbourGrid::ColumnsAround(std::uint32_t column) {
  if (!columns_around_known_[column]) {
    columns_around_[column] = ColumnsAround(columns_[column].x, columns_[column].y);
    columns_around_known_[column] = 1;
  }
  return columns_around_[column];
}

// The slots of `column`'s cells z - 1, z and z + 1, which follow each other in a column sorted by
// z (absent cells: empty).
NeighbourGrid::Stretch NeighbourGrid::CellsAround(std::uint32_t column, std::int64_t z) const {
  if (column == kNone) return {{0, 0, 0, 0}};
  const std::int64_t* z_last = run_z_.data() + columns_[column].end_run;
  const std::int64_t* it =
      std::lower_bound(run_z_.data() + columns_[column].first_run, z_last, z - 1);
  // A column's end: the next run's begin.
  const auto begin_of = [&](const std::int64_t* r) {
    return runs_[std::size_t(r - run_z_.data())].begin;
  };
  Stretch s;
  for (std::int64_t dz = -1; dz <= 1; ++dz) {
    s.bound[dz + 1] = begin_of(it);
    if (it != z_last && *it == z + dz) ++it;
  }
  s.bound[3] = begin_of(it);
  return s;
}

// `column`: the cell's own, kNone when no particle is binned in it.
NeighbourGrid::Neighbourhood NeighbourGrid::NeighbourhoodOfCell(const Cell& c,
                                                                std::uint32_t column) {
  const Around around = column == kNone ? ColumnsAround(c[0], c[1]) : ColumnsAround(column);
  Neighbourhood n{c, {}};
  for (std::size_t k = 0; k < around.size(); ++k) n.columns[k] = CellsAround(around[k], c[2]);
  return n;
}

// Every query particle is binned (it lies in its own block, within the padded box), so its
// cell's neighbourhood is computed once, from its column's neighbours computed once.
const NeighbourGrid::Neighbourhood& NeighbourGrid::NeighbourhoodOf(std::size_t centre,
                                                                   const float* x) {
  const std::uint32_t run = run_of_particle_[centre];
  if (run == kNone) {
    const Cell c = CellOf(x, radius_cu_);
    return scratch_ = NeighbourhoodOfCell(c, FindColumn(c[0], c[1]));
  }
  // A cell of one particle (most, at held_pair's radius) is asked once: nothing kept.
  if (runs_[run + 1].begin - runs_[run].begin == 1)
    return scratch_ = NeighbourhoodOfCell(runs_[run].cell, runs_[run].column);
  if (neighbourhood_of_run_[run] == kNone) {
    neighbourhood_of_run_[run] = std::uint32_t(neighbourhoods_.size());
    neighbourhoods_.push_back(NeighbourhoodOfCell(runs_[run].cell, runs_[run].column));
  }
  return neighbourhoods_[neighbourhood_of_run_[run]];
}

}  // namespace owval::compare::internal
