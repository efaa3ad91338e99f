#pragma once
// SPH density from the neighbour lists (sphFluid.cl:473-510): Wpoly6 over the ≤32 listed
// neighbours of any type, no self term, floored at hS⁶ (what a self term would add).
#include <algorithm>
#include <vector>

#include "kernels/kernels.hpp"
#include "kernels/sph_constants.hpp"
#include "neighbours/neighbour_grid.hpp"
#include "state/particle_state.hpp"

namespace owval::engine::internal {

// Σ (h² − r²)³ over one particle's listed neighbours, r² = r2_of(slot) in whatever unit h2 is
// in: the one Wpoly6 density sum of every density (ρ from x(t), PCISPH's ρ* from x*).
template <typename SquaredDistance>
float Wpoly6Sum(float h2, const Neighbour* slots, SquaredDistance r2_of) {
  float sum = 0;
  for (int n = 0; n < kSlots && slots[n].index >= 0; ++n)
    sum = AccumulateWpoly6(h2, r2_of(slots[n]), sum);
  return sum;
}

// ρ = m·Wpoly6 coefficient · Σ(hS² − r²)³ (sum in m⁶), floored at hS⁶: what a self term would
// add.
inline float Wpoly6Density(const SphConstants& k, float sum_m6) {
  return k.mass_wpoly6 * std::max(sum_m6, k.hs6);
}

// Σ (hS² − r²)³ over one particle's slots, r from the list (metres).
float DensitySum(const SphConstants& k, const Neighbour* slots);

// ρ of every active particle (moving ones and the boundary particles next to them).
void ComputeDensity(const SphConstants& k, ParticleState* state, int threads);

// ρ of every particle at the current positions, for output: the step's value where it computed
// one, a fresh sum for boundary particles far from the action. A boundary particle whose search
// cells hold no moving particle has the density it had the last time that was true, so Of() sums
// it once and keeps it; a solver holds one OutputDensity for the run.
class OutputDensity {
 public:
  std::vector<float> Of(const SphConstants& k, const NeighbourGrid& grid,
                        const ParticleState& state);

 private:
  std::vector<float> boundary_only_;  // per row; −1 where not computed yet
};

}  // namespace owval::engine::internal
