#include "neighbours/cell_list.hpp"

#include <algorithm>
#include <cmath>

#include "owval/base/memory_budget.hpp"

namespace owval::engine::internal {
namespace {

// Spreads the low 10 bits of v so that two zero bits separate each.
std::uint32_t Spread(std::uint32_t v) {
  v &= 0x3ff;
  v = (v | (v << 16)) & 0x030000ff;
  v = (v | (v << 8)) & 0x0300f00f;
  v = (v | (v << 4)) & 0x030c30c3;
  v = (v | (v << 2)) & 0x09249249;
  return v;
}

}  // namespace

void CellList::Configure(const float low[3], const float high[3], float cell_size) {
  inverse_size_ = 1.0f / cell_size;
  int n[3];
  std::size_t total = 1;
  for (int a = 0; a < 3; ++a) {
    low_[a] = low[a];
    const double extent = std::max(0.0, double(high[a]) - double(low[a]));
    n[a] = int(std::min(1e9, std::floor(extent / cell_size))) + 1;
    total = SaturatingProduct(total, std::size_t(n[a]));
  }
  CheckAllocation(SaturatingProduct(total, 8), "wcsph", "cell list over the simulation box");
  nx_ = n[0];
  ny_ = n[1];
  nz_ = n[2];
  start_.assign(total + 1, 0);
  fill_.assign(total, 0);
}

int CellList::Cell(float x, float y, float z) const {
  const auto coordinate = [&](float v, int axis, int count) {
    const int c = int(std::floor((v - low_[axis]) * inverse_size_));
    return std::clamp(c, 0, count - 1);
  };
  return coordinate(x, 0, nx_) + nx_ * (coordinate(y, 1, ny_) + ny_ * coordinate(z, 2, nz_));
}

void CellList::Build(const float* x, const float* y, const float* z, std::size_t n) {
  cell_of_.resize(n);
  items_.resize(n);
  std::fill(start_.begin(), start_.end(), 0);
  for (std::size_t i = 0; i < n; ++i) {
    cell_of_[i] = Cell(x[i], y[i], z[i]);
    ++start_[cell_of_[i] + 1];
  }
  for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
  std::copy(start_.begin(), start_.end() - 1, fill_.begin());
  for (std::size_t i = 0; i < n; ++i) items_[fill_[cell_of_[i]]++] = std::int32_t(i);
}

int CellList::Around(int cell, int out[27]) const {
  const int cx = cell % nx_, cy = (cell / nx_) % ny_, cz = cell / (nx_ * ny_);
  int count = 0;
  for (int dz = -1; dz <= 1; ++dz) {
    const int z = cz + dz;
    if (z < 0 || z >= nz_) continue;
    for (int dy = -1; dy <= 1; ++dy) {
      const int y = cy + dy;
      if (y < 0 || y >= ny_) continue;
      for (int dx = -1; dx <= 1; ++dx) {
        const int x = cx + dx;
        if (x < 0 || x >= nx_) continue;
        out[count++] = x + nx_ * (y + ny_ * z);
      }
    }
  }
  return count;
}

void CellList::Bounds(int cell, float low[3], float high[3]) const {
  const int at[3] = {cell % nx_, (cell / nx_) % ny_, cell / (nx_ * ny_)};
  const float size = 1.0f / inverse_size_;
  for (int a = 0; a < 3; ++a) {
    low[a] = low_[a] + float(at[a]) * size;
    high[a] = low[a] + size;
  }
}

std::uint32_t CellList::MortonKey(int cell) const {
  const std::uint32_t cx = std::uint32_t(cell % nx_), cy = std::uint32_t((cell / nx_) % ny_),
                      cz = std::uint32_t(cell / (nx_ * ny_));
  return Spread(cx) | (Spread(cy) << 1) | (Spread(cz) << 2);
}

}  // namespace owval::engine::internal
