#pragma once
// SPH density from the neighbour lists (sphFluid.cl:473-510): Wpoly6 over the ≤32 listed
// neighbours of any type, no self term, floored at hS⁶ (what a self term would add).
#include <vector>

#include "kernels/sph_constants.hpp"
#include "neighbours/neighbour_grid.hpp"
#include "state/particle_state.hpp"

namespace owval::engine::internal {

// Σ (hS² − r²)³ over one particle's slots, r from the list (metres).
float DensitySum(const SphConstants& k, const Neighbour* slots);

// ρ of every active particle (moving ones and the boundary particles next to them).
void ComputeDensity(const SphConstants& k, ParticleState* state, int threads);

// ρ of every particle at the current positions: the step's value where it computed one, a fresh
// sum for boundary particles far from the action. For output.
std::vector<float> DensityOfAll(const SphConstants& k, const NeighbourGrid& grid,
                                const ParticleState& state);

}  // namespace owval::engine::internal
