#pragma once
// A uniform cell list for schemes that need every neighbour within a radius (the WCSPH scheme's
// kernel sums): cells one support radius wide, the 27 cells around a particle searched, no cap on
// the neighbour count. Sibernetic's grid (neighbour_grid.hpp) keeps only the 32 nearest within h,
// which the PCISPH path must reproduce but a Wendland kernel sum must not truncate.
//
// Also the Morton (Z-order) key of a particle's cell, by which a scheme can reorder its particle
// arrays so that neighbours in space are neighbours in memory.
#include <cstdint>
#include <vector>

namespace owval::engine::internal {

class CellList {
 public:
  // Cells of `cell_size` (m) over [low, high] on each axis (positions outside are clamped into
  // the edge cells). Throws InputError when the grid exceeds the memory budget.
  void Configure(const float low[3], const float high[3], float cell_size);

  // Bins n particles (structure of arrays, metres): a counting sort by cell, stable in index.
  void Build(const float* x, const float* y, const float* z, std::size_t n);

  int Cell(float x, float y, float z) const;
  int cells() const { return nx_ * ny_ * nz_; }
  // The cell of particle i at the last Build.
  int CellOf(std::size_t i) const { return cell_of_[i]; }
  // The particles of one cell, in ascending index order.
  const std::int32_t* begin(int cell) const { return &items_[start_[cell]]; }
  const std::int32_t* end(int cell) const { return &items_[start_[cell + 1]]; }
  // The (up to) 27 cells around `cell`, itself included; returns how many.
  int Around(int cell, int out[27]) const;
  // The cell's extent (m): [low, high) on each axis.
  void Bounds(int cell, float low[3], float high[3]) const;
  // The Morton key of a cell: its coordinates' bits interleaved (10 bits per axis).
  std::uint32_t MortonKey(int cell) const;

 private:
  float low_[3] = {0, 0, 0};
  float inverse_size_ = 1;
  int nx_ = 1, ny_ = 1, nz_ = 1;
  std::vector<std::int32_t> start_, items_, cell_of_, fill_;
};

}  // namespace owval::engine::internal
