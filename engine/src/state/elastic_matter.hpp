#pragma once
// What elastic particles carry besides their state: springs, membrane triangles and the muscle
// signal. Elastic particles are the configuration's first rows, so row e < particle_count
// indexes all of these (sphFluid.cl:693-700).
#include <array>
#include <cstddef>
#include <vector>

#include "state/particle_state.hpp"

namespace owval::engine::internal {

constexpr int kSpringSlots = 32;   // per elastic particle; the first empty partner ends them
constexpr int kMembraneSlots = 7;  // triangles listed per elastic particle
constexpr int kMuscles = 96;       // Sibernetic's signal vector

struct ElasticMatter {
  std::size_t particle_count = 0;
  // kSpringSlots per particle: partner row (float, −1 empty), rest length in metres, muscle id,
  // unused.
  std::vector<Float4> springs;
  std::vector<std::array<int, 3>> membranes;  // triangles of elastic rows
  std::vector<int> membrane_index;            // kMembraneSlots per particle, −1 = none
  std::vector<float> muscle_activation = std::vector<float>(kMuscles, 0.0f);
};

}  // namespace owval::engine::internal
