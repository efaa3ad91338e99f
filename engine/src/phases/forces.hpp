#pragma once
// Non-pressure accelerations of one step, from x(t) and v(t):
//   viscosity + gravity + surface tension (sphFluid.cl:519-667), then springs and muscles
//   (sphFluid.cl:674-748), added once per step outside any pressure loop.
#include "kernels/sph_constants.hpp"
#include "state/elastic_matter.hpp"
#include "state/particle_state.hpp"

namespace owval::engine::internal {

// acceleration = viscosity + gravity + surface tension for every active non-boundary particle
// (boundary particles get zero). Viscosity uses 1e-5 between worm body and agar and 1e-4
// otherwise, a boundary's velocity counted as zero; surface tension (cohesion) acts between all
// listed pairs, walls included, on cu differences.
void ComputeViscosityGravitySurfaceTension(const SphConstants& k, ParticleState* state,
                                           int threads);

// Adds each elastic particle's springs, one slot at a time: −r̂·(r − L0)·k, with full k only
// between two worm-body particles and non_worm_body_spring_factor·k otherwise, plus −r̂·signal·F
// for a muscle whose signal is positive. One-sided: a particle feels only its own rows.
void AddSpringForces(const SphConstants& k, const ElasticMatter& matter, ParticleState* state,
                     int threads);

}  // namespace owval::engine::internal
