#pragma once
// Time integration of the moving particles from a = acceleration + the scheme's pressure
// acceleration (one per particle, m/s²), with
// the wall correction applied to the new position and velocity (sphFluid.cl:1329-1483).
// At a run's first step nothing moves: the integrators only remember a (sphFluid.cl:1368-1373).
#include <vector>

#include "kernels/sph_constants.hpp"
#include "state/particle_state.hpp"

namespace owval::engine::internal {

// Semi-implicit (symplectic) Euler, Sibernetic's default: v' = v + a·dt, x' = x + v'·dt/s.
void IntegrateSemiImplicitEuler(const SphConstants& k,
                                const std::vector<Float4>& pressure_acceleration,
                                ParticleState* state, bool first_step, int threads);

// Leapfrog, first half (right after the neighbour search, not at the first step):
// x' = x + (v·dt + a_prev·dt²/2)/s.
void MovePositionsLeapfrog(const SphConstants& k, ParticleState* state, int threads);

// Leapfrog, second half: v' = v + (a_prev + a)·dt/2, then the wall correction on the moved x.
void IntegrateLeapfrogVelocities(const SphConstants& k,
                                 const std::vector<Float4>& pressure_acceleration,
                                 ParticleState* state, bool first_step, int threads);

}  // namespace owval::engine::internal
