#include "state/non_finite.hpp"

#include <cmath>

namespace owval::engine::internal {
namespace {

bool Finite(const Float4& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace

Solver::NonFinite FirstNonFiniteOf(std::span<const Float4> position,
                                   std::span<const Float4> velocity,
                                   const std::vector<std::int32_t>& moving) {
  for (const std::int32_t i : moving)
    if (!Finite(position[std::size_t(i)])) return {i, "position"};
  for (const std::int32_t i : moving)
    if (!Finite(velocity[std::size_t(i)])) return {i, "velocity"};
  return {};
}

}  // namespace owval::engine::internal
