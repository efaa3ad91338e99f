#pragma once
// Order statistics the scene gates summarise a frame's particles by (liquid_packing,
// frame_acceleration).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace owval::compare::internal {

// The q-th quantile of `values` (0 <= q <= 1, values not empty), by the nearest rank; reorders
// them.
inline double Quantile(std::vector<double>& values, double q) {
  const auto rank = std::size_t(std::lround(q * double(values.size() - 1)));
  std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(rank), values.end());
  return values[rank];
}

}  // namespace owval::compare::internal
