#pragma once
// The SPH pressure-gradient acceleration with the spiky kernel's gradient, as Sibernetic computes
// it (sphFluid.cl:960-1030): a_p,i = m∇W/ρ_i · Σ_j −(hS − r)²/2 · (p_i + p_j)/ρ_j · x̂_ij, with
// x(t) distances and directions whatever density the caller passes. Below hS/4 a fixed
// short-range repulsion replaces the pressure pair term. Shared by every scheme with pressures.
#include <vector>

#include "kernels/sph_constants.hpp"
#include "state/particle_state.hpp"

namespace owval::engine::internal {

// Fills out[i] for every moving particle i. density: ρ per particle (PCISPH: the predicted ρ*);
// short_range_pressure: the pressure (Pa) the repulsion below hS/4 uses for p_i + p_j
// (PCISPH: ρ0·δ).
void ComputePressureAcceleration(const SphConstants& k, const ParticleState& state,
                                 const std::vector<float>& density, float short_range_pressure,
                                 std::vector<Float4>* out, int threads);

}  // namespace owval::engine::internal
