#include "phases/density.hpp"

#include <algorithm>

namespace owval::engine::internal {

float DensitySum(const SphConstants& k, const Neighbour* slots) {
  // r² from the listed distance, in metres; the sum fused as at sphFluid.cl:499.
  return Wpoly6Sum(k.hs2_m2, slots,
                   [](const Neighbour& slot) { return slot.distance_m * slot.distance_m; });
}

void ComputeDensity(const SphConstants& k, ParticleState* state, int threads) {
  ParticleState& s = *state;
#pragma omp parallel for schedule(static) num_threads(threads)
  for (std::size_t n = 0; n < s.active.size(); ++n) {
    const std::int32_t i = s.active[n];
    s.density[i] = Wpoly6Density(k, DensitySum(k, s.slots(i)));
  }
}

std::vector<float> OutputDensity::Of(const SphConstants& k, const NeighbourGrid& grid,
                                     const ParticleState& state) {
  std::vector<float> density(state.size());
  boundary_only_.resize(state.size(), -1.0f);
  Neighbour slots[kSlots];
  for (std::size_t i = 0; i < state.size(); ++i) {
    if (grid.IsActive(std::int32_t(i))) {
      density[i] = state.density[i];
      continue;
    }
    const bool fixed =
        IsBoundary(state.position[i].w) && grid.SearchesOnlyBoundary(state, std::int32_t(i));
    if (fixed && boundary_only_[i] > 0) {  // densities are > 0
      density[i] = boundary_only_[i];
      continue;
    }
    grid.FindNeighbours(state, std::int32_t(i), slots);
    density[i] = Wpoly6Density(k, DensitySum(k, slots));
    if (fixed) boundary_only_[i] = density[i];
  }
  return density;
}

}  // namespace owval::engine::internal
