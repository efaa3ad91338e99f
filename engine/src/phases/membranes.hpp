#pragma once
// Liquid-impermeable membranes (sphFluid.cl:1042-1322). After integration, each liquid particle
// near elastic particles that belong to membrane triangles is pushed out along the averaged
// triangle normals, weighted as at walls [IAGT10]; velocities are untouched. Quirks kept
// (gotcha 16): the particle–membrane distance drops z and keeps the type codes' difference, and
// a degenerate triangle, or a particle lying on a triangle's plane, cancels that particle's whole
// correction for the step.
#include <cmath>
#include <vector>

#include "kernels/sph_constants.hpp"
#include "state/elastic_matter.hpp"
#include "state/particle_state.hpp"

namespace owval::engine::internal {

// The distance by which Sibernetic selects a liquid particle's membranes through elastic
// neighbour j: z dropped and the type codes' difference kept (a slip in Sibernetic's port,
// commit 839ee75; gotcha 16). XPBD's membrane constraint selects by the same rule.
inline float MembraneDistance(const Float4& liquid, const Float4& elastic) {
  const float dx = liquid.x - elastic.x, dy = liquid.y - elastic.y, dw = liquid.w - elastic.w;
  return std::sqrt(dx * dx + dy * dy + dw * dw);
}

// scratch holds the per-particle corrections until all are known (the pass reads positions it
// then moves).
void InteractWithMembranes(const SphConstants& k, const ElasticMatter& matter, ParticleState* state,
                           std::vector<Float4>* scratch, int threads);

}  // namespace owval::engine::internal
