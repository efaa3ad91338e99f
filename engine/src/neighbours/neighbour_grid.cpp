#include "neighbours/neighbour_grid.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>

#include "neighbours/near_candidates.hpp"

namespace owval::engine::internal {
namespace {

// Counting sort of particle indices into cells; indices stay ascending within a cell, as
// Sibernetic's (stable, on glibc) sort by cell leaves them.
void Bin(const std::vector<std::int32_t>& particles, const std::vector<int>& cell_of, int cells,
         std::vector<std::int32_t>* start, std::vector<std::int32_t>* items) {
  start->assign(cells + 1, 0);
  for (std::size_t n = 0; n < particles.size(); ++n) ++(*start)[cell_of[n] + 1];
  for (int c = 0; c < cells; ++c) (*start)[c + 1] += (*start)[c];
  items->resize(particles.size());
  std::vector<std::int32_t> fill(start->begin(), start->end() - 1);
  for (std::size_t n = 0; n < particles.size(); ++n) (*items)[fill[cell_of[n]]++] = particles[n];
}

// Sibernetic's acceptance rule: a candidate no farther than the current target slot takes it;
// the first 32 fill slots in order, after that the target is the (first) farthest slot. Offered
// candidates are within h (NearCandidates), so while slots are empty each one takes the next
// slot: they are copied in bulk, and only later ones are compared.
struct Selection {
  // Twice the slots: the bulk fill copies a whole block of kSlots entries at `filled` (a copy of
  // constant size is a few vector moves; a variable one was a call to memmove per cell). Only
  // entries below `filled` are ever read, so what lands beyond is never seen.
  float distance2[2 * kSlots];
  std::int32_t index[2 * kSlots];
  int filled = 0, target = 0;  // target: the first farthest slot, once all are filled

  // j and d2 hold n candidates and are readable for kSlots entries at least.
  void OfferNear(const std::int32_t* j, const float* d2, int n) {
    const int copy = std::min(n, kSlots - filled);
    if (copy > 0) {
      std::memcpy(index + filled, j, kSlots * sizeof *j);
      std::memcpy(distance2 + filled, d2, kSlots * sizeof *d2);
    }
    filled += copy;
    if (copy > 0 && filled == kSlots) target = FirstLargestOf32(distance2);
    for (int m = copy; m < n; ++m) {
      if (!(d2[m] <= distance2[target])) continue;
      distance2[target] = d2[m];
      index[target] = j[m];
      target = FirstLargestOf32(distance2);
    }
  }
};

}  // namespace

NeighbourGrid::NeighbourGrid(const Box& box, const SphConstants& k) : box_(box), k_(k) {
  cell_size_ = k.cell_size_cu;
  cell_size_inverse_ = k.cell_size_inverse;
  // Cell coordinates are (int)(x / 2h) without subtracting xmin (sphFluid.cl:142-156).
  nx_ = std::max(1, int(std::max(box.xmax, 0.0f) * cell_size_inverse_) + 2);
  ny_ = std::max(1, int(std::max(box.ymax, 0.0f) * cell_size_inverse_) + 2);
  nz_ = std::max(1, int(std::max(box.zmax, 0.0f) * cell_size_inverse_) + 2);
}

int NeighbourGrid::CellCoordinate(float x, int axis) const {
  const int n = axis == 0 ? nx_ : axis == 1 ? ny_ : nz_;
  return std::clamp(int(x * cell_size_inverse_), 0, n - 1);
}

void NeighbourGrid::SetStatic(const ParticleState& s) {
  std::vector<std::int32_t> boundary;
  std::vector<int> cell_of;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (!IsBoundary(s.position[i].w)) continue;
    boundary.push_back(std::int32_t(i));
    const Float4& p = s.position[i];
    cell_of.push_back(
        CellIndex(CellCoordinate(p.x, 0), CellCoordinate(p.y, 1), CellCoordinate(p.z, 2)));
  }
  Bin(boundary, cell_of, nx_ * ny_ * nz_, &static_start_, &static_items_);
  for (std::int32_t b : static_items_) {
    static_x_.push_back(s.position[b].x);
    static_y_.push_back(s.position[b].y);
    static_z_.push_back(s.position[b].z);
  }
  boundary_.assign(s.size(), 0);
  for (std::int32_t b : boundary) boundary_[std::size_t(b)] = 1;
  static_rank_.assign(s.size(), -1);
  for (std::size_t r = 0; r < static_items_.size(); ++r)
    static_rank_[std::size_t(static_items_[r])] = std::int32_t(r);
  listed_.assign((static_items_.size() + 7) / 8 * 8, 0);  // whole 8-byte words for ListActive
  merged_start_.assign(std::size_t(nx_) * ny_ * nz_, -1);
  merged_count_.assign(std::size_t(nx_) * ny_ * nz_, 0);
}

void NeighbourGrid::UpdateMoving(const ParticleState& s) {
  std::vector<int> cell_of(s.moving.size());
  for (std::size_t n = 0; n < s.moving.size(); ++n) {
    const Float4& p = s.position[s.moving[n]];
    cell_of[n] = CellIndex(CellCoordinate(p.x, 0), CellCoordinate(p.y, 1), CellCoordinate(p.z, 2));
  }
  Bin(s.moving, cell_of, nx_ * ny_ * nz_, &moving_start_, &moving_items_);
  MergeCells(s, cell_of);
}

void NeighbourGrid::MergeCells(const ParticleState& s, const std::vector<int>& moving_cells) {
  for (int c : merged_cells_) merged_start_[c] = -1;
  merged_cells_.clear();
  for (int c : moving_cells) {
    if (merged_start_[c] >= 0) continue;
    merged_start_[c] = 0;  // marked; offsets are set below
    merged_cells_.push_back(c);
  }
  merged_items_.clear();
  merged_x_.clear();
  merged_y_.clear();
  merged_z_.clear();
  for (int c : merged_cells_) {
    merged_start_[c] = std::int32_t(merged_items_.size());
    // Merge the two ascending lists so candidates arrive in ascending index order, as in
    // Sibernetic's cell-sorted array.
    std::int32_t a = moving_start_[c], a_end = moving_start_[c + 1];
    std::int32_t b = static_start_[c], b_end = static_start_[c + 1];
    while (a < a_end || b < b_end) {
      const bool take_moving = b >= b_end || (a < a_end && moving_items_[a] < static_items_[b]);
      const std::int32_t j = take_moving ? moving_items_[a++] : static_items_[b++];
      merged_items_.push_back(j);
      merged_x_.push_back(s.position[j].x);
      merged_y_.push_back(s.position[j].y);
      merged_z_.push_back(s.position[j].z);
    }
    merged_count_[c] = std::int32_t(merged_items_.size()) - merged_start_[c];
  }
}

NeighbourGrid::Segment NeighbourGrid::CellSegment(int cell) const {
  const std::int32_t m = merged_start_[cell];
  if (m >= 0)
    return {&merged_items_[m], &merged_x_[m], &merged_y_[m], &merged_z_[m], merged_count_[cell]};
  const std::int32_t b = static_start_[cell];
  return {static_items_.data() + b, static_x_.data() + b, static_y_.data() + b,
          static_z_.data() + b, static_start_[cell + 1] - b};
}

void NeighbourGrid::SearchCells(const Float4& p, int cells[8]) const {
  const int c[3] = {CellCoordinate(p.x, 0), CellCoordinate(p.y, 1), CellCoordinate(p.z, 2)};
  const float origin[3] = {box_.xmin, box_.ymin, box_.zmin};
  const float x[3] = {p.x, p.y, p.z};
  int delta[3];
  for (int a = 0; a < 3; ++a) {
    // Nearer half of the cell: search toward lower cells when in the low half.
    const float corner = float(c[a]) * cell_size_;
    delta[a] = (x[a] - origin[a]) - corner < k_.h_cu ? -1 : 1;
  }
  const int offsets[8][3] = {{0, 0, 0},
                             {delta[0], 0, 0},
                             {0, delta[1], 0},
                             {0, 0, delta[2]},
                             {delta[0], delta[1], 0},
                             {delta[0], 0, delta[2]},
                             {0, delta[1], delta[2]},
                             {delta[0], delta[1], delta[2]}};
  for (int n = 0; n < 8; ++n) {
    const int cx = c[0] + offsets[n][0], cy = c[1] + offsets[n][1], cz = c[2] + offsets[n][2];
    const bool inside = cx >= 0 && cy >= 0 && cz >= 0 && cx < nx_ && cy < ny_ && cz < nz_;
    cells[n] = inside ? CellIndex(cx, cy, cz) : -1;
  }
}

bool NeighbourGrid::SearchesOnlyBoundary(const ParticleState& s, std::int32_t i) const {
  int cells[8];
  SearchCells(s.position[i], cells);
  for (int c : cells)
    if (c >= 0 && merged_start_[c] >= 0) return false;
  return true;
}

void NeighbourGrid::FindNeighbours(const ParticleState& s, std::int32_t i, Neighbour* slots) const {
  const Float4 p = s.position[i];
  int cells[8];
  SearchCells(p, cells);
  CandidateCell searched[8];
  int searched_count = 0, candidates = 0;
  for (const int c : cells) {
    if (c < 0) continue;
    const Segment cell = CellSegment(c);
    searched[searched_count++] = {cell.index, cell.x, cell.y, cell.z, cell.count};
    candidates += cell.count;
  }
  // Only candidates within h can ever be taken (the selection's limit starts at h² and only
  // falls): NearCandidatesOfCells packs those of all eight cells, in the cells' order, and only
  // they are offered, at once. The buffers grow to the largest neighbourhood seen.
  thread_local std::vector<std::int32_t> near_index;
  thread_local std::vector<float> near_d2;
  if (near_index.size() < std::size_t(candidates + kNearSlack)) {
    near_index.resize(std::size_t(candidates + kNearSlack) * 2);
    near_d2.resize(near_index.size());
  }
  const float position[3] = {p.x, p.y, p.z};
  const int near = NearCandidatesOfCells(searched, searched_count, position, k_.h2_cu, i,
                                         near_index.data(), near_d2.data());
  Selection selection;
  selection.OfferNear(near_index.data(), near_d2.data(), near);
  for (int k = 0; k < selection.filled; ++k)
    slots[k] = {selection.index[k], std::sqrt(selection.distance2[k]) * k_.scale};
  for (int k = selection.filled; k < kSlots; ++k) slots[k] = Neighbour{};
}

std::uint32_t NeighbourGrid::BoundarySlots(const Neighbour* slots) const {
  std::uint32_t mask = 0;
  for (int n = 0; n < kSlots && slots[n].index >= 0; ++n)
    mask |= std::uint32_t(boundary_[std::size_t(slots[n].index)]) << n;
  return mask;
}

void NeighbourGrid::ListSlots(ParticleState* state, std::int32_t i) {
  ParticleState& s = *state;
  Neighbour* slots = s.slots(std::size_t(i));
  FindNeighbours(s, i, slots);
  const std::uint32_t mask = BoundarySlots(slots);
  s.boundary_slots[std::size_t(i)] = mask;
  // Marks the boundary particles a moving particle lists, by their place in the boundary cell
  // lists, for ListActive (every write stores 1). Bin placed every boundary particle in them.
  if (!boundary_[std::size_t(i)])
    for (std::uint32_t bits = mask; bits != 0; bits &= bits - 1) {
      const std::int32_t rank = static_rank_[std::size_t(slots[__builtin_ctz(bits)].index)];
      std::atomic_ref<std::uint8_t>(listed_[std::size_t(rank)]).store(1, std::memory_order_relaxed);
    }
}

void NeighbourGrid::ListActive(ParticleState* state) {
  ParticleState& s = *state;
  for (std::int32_t b : s.active) is_active_[b] = 0;
  s.active = s.moving;
  for (std::int32_t i : s.moving) is_active_[i] = 1;
  // The boundary particles some moving particle lists (marked by ListSlots), in the order of the
  // boundary cell lists. Their order in `active` changes no result: each active particle's
  // quantities come from its own list alone.
  // The marks are read eight at a time: a step marks a few hundred of demo1's 17,498 boundary
  // particles, and visiting each one's mark was 5% of a step.
  for (std::size_t first = 0; first < listed_.size(); first += 8) {
    std::uint64_t word;
    std::memcpy(&word, &listed_[first], sizeof word);
    if (word == 0) continue;
    std::memset(&listed_[first], 0, sizeof word);
    for (; word != 0; word &= word - 1) {
      const std::int32_t b = static_items_[first + std::size_t(__builtin_ctzll(word)) / 8];
      is_active_[b] = 1;
      s.active.push_back(b);
    }
  }
}

void NeighbourGrid::Refresh(ParticleState* state, int threads) {
  ParticleState& s = *state;
  UpdateMoving(s);
  const auto& moving = s.moving;
  s.boundary_slots.resize(s.size(), 0);
#pragma omp parallel for schedule(static) num_threads(threads)
  for (std::size_t n = 0; n < moving.size(); ++n) ListSlots(&s, moving[n]);
  is_active_.resize(s.size(), 0);
  ListActive(&s);
  const std::size_t first_boundary = moving.size();
#pragma omp parallel for schedule(static) num_threads(threads)
  for (std::size_t n = first_boundary; n < s.active.size(); ++n) ListSlots(&s, s.active[n]);
}

}  // namespace owval::engine::internal
