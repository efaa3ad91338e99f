#pragma once
// Solver::FirstNonFinite over the particles a scheme moves: a list of them (boundary particles
// never change), or any range of indices.
#include <cmath>
#include <cstdint>
#include <span>

#include "owval/engine/solver.hpp"

namespace owval::engine::internal {

// The first of `particles` (indices) whose position is not finite, else the first whose velocity
// is not.
template <typename Particles>
Solver::NonFinite FirstNonFiniteOf(std::span<const Float4> position,
                                   std::span<const Float4> velocity, Particles&& particles) {
  const auto finite = [](const Float4& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
  };
  for (const auto i : particles)
    if (!finite(position[std::size_t(i)])) return {std::int64_t(i), "position"};
  for (const auto i : particles)
    if (!finite(velocity[std::size_t(i)])) return {std::int64_t(i), "velocity"};
  return {};
}

}  // namespace owval::engine::internal
