#pragma once
// Turning a configuration into particle state, for any scheme: positions and velocities in row
// order, the moving particles listed, and the elastic matter (springs with rest lengths in
// metres, membranes, muscle slots).
#include "kernels/sph_constants.hpp"
#include "owval/engine/config.hpp"
#include "state/elastic_matter.hpp"
#include "state/particle_state.hpp"

namespace owval::engine::internal {

// Sizes state for the configuration's particles and fills position, velocity and moving.
void LoadParticles(const SiberneticConfig& config, ParticleState* state);

// Springs, membranes and membrane index of the configuration's elastic particles. Rest lengths
// are converted to metres with k.scale, as Sibernetic does on load (owHelper.cpp:328-329).
ElasticMatter ElasticMatterOf(const SiberneticConfig& config, const SphConstants& k);

}  // namespace owval::engine::internal
