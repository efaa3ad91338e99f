#include "state/initial_state.hpp"

namespace owval::engine::internal {
namespace {

Float4 ToFloat4(const Row4& r) { return {r[0], r[1], r[2], r[3]}; }

}  // namespace

void LoadParticles(const SiberneticConfig& config, ParticleState* state) {
  ParticleState& s = *state;
  const std::size_t n = config.particle_count();
  s.Resize(n);
  s.moving.clear();
  for (std::size_t i = 0; i < n; ++i) {
    s.position[i] = ToFloat4(config.position[i]);
    s.velocity[i] = ToFloat4(config.velocity[i]);
    if (!IsBoundary(s.position[i].w)) s.moving.push_back(std::int32_t(i));
  }
}

ElasticMatter ElasticMatterOf(const SiberneticConfig& config, const SphConstants& k) {
  ElasticMatter matter;
  matter.particle_count = config.elastic_count();
  for (const Row4& c : config.connection)
    matter.springs.push_back({c[0], c[1] * k.scale, c[2], c[3]});
  matter.membranes = config.membranes;
  matter.membrane_index = config.particle_mem_index;
  return matter;
}

}  // namespace owval::engine::internal
