#pragma once
// Liquid-impermeable membranes (sphFluid.cl:1042-1322). After integration, each liquid particle
// near elastic particles that belong to membrane triangles is pushed out along the averaged
// triangle normals, weighted as at walls [IAGT10]; velocities are untouched. Quirks kept
// (gotcha 16): the particle–membrane distance drops z and keeps the type codes' difference, and
// a degenerate triangle, or a particle lying on a triangle's plane, cancels that particle's whole
// correction for the step.
#include <vector>

#include "kernels/sph_constants.hpp"
#include "state/elastic_matter.hpp"
#include "state/particle_state.hpp"

namespace owval::engine::internal {

// scratch holds the per-particle corrections until all are known (the pass reads positions it
// then moves).
void InteractWithMembranes(const SphConstants& k, const ElasticMatter& matter, ParticleState* state,
                           std::vector<Float4>* scratch, int threads);

}  // namespace owval::engine::internal
