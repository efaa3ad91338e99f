#pragma once
// Solver::FirstNonFinite over a list of the moving particles (boundary particles never change).
#include <cstdint>
#include <span>
#include <vector>

#include "owval/engine/solver.hpp"

namespace owval::engine::internal {

// The first of `moving` whose position is not finite, else the first whose velocity is not.
Solver::NonFinite FirstNonFiniteOf(std::span<const Float4> position,
                                   std::span<const Float4> velocity,
                                   const std::vector<std::int32_t>& moving);

}  // namespace owval::engine::internal
