#include "phases/density.hpp"

#include <algorithm>

namespace owval::engine::internal {

float DensitySum(const SphConstants& k, const Neighbour* slots) {
  float sum = 0;
  for (int n = 0; n < kSlots && slots[n].index >= 0; ++n) {
    const float r2 = slots[n].distance_m * slots[n].distance_m;
    if (r2 < k.hs2_m2) {
      const float q = k.hs2_m2 - r2;
      sum = Fma(q * q, q, sum);  // sphFluid.cl:499
    }
  }
  return sum;
}

void ComputeDensity(const SphConstants& k, ParticleState* state, int threads) {
  ParticleState& s = *state;
#pragma omp parallel for schedule(static) num_threads(threads)
  for (std::size_t n = 0; n < s.active.size(); ++n) {
    const std::int32_t i = s.active[n];
    s.density[i] = k.mass_wpoly6 * std::max(DensitySum(k, s.slots(i)), k.hs6);
  }
}

std::vector<float> DensityOfAll(const SphConstants& k, const NeighbourGrid& grid,
                                const ParticleState& state) {
  std::vector<float> density(state.size());
  Neighbour slots[kSlots];
  for (std::size_t i = 0; i < state.size(); ++i) {
    if (grid.IsActive(std::int32_t(i))) {
      density[i] = state.density[i];
      continue;
    }
    grid.FindNeighbours(state, std::int32_t(i), slots);
    density[i] = k.mass_wpoly6 * std::max(DensitySum(k, slots), k.hs6);
  }
  return density;
}

}  // namespace owval::engine::internal
