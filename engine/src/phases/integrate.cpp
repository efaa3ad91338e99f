#include "phases/integrate.hpp"

#include "phases/walls.hpp"

namespace owval::engine::internal {
namespace {

Float4 TotalAcceleration(const ParticleState& s, std::int32_t i) {
  const Float4 a = s.acceleration[i], ap = s.pressure_acceleration[i];
  return {a.x + ap.x, a.y + ap.y, a.z + ap.z, 0};
}

}  // namespace

void IntegrateSemiImplicitEuler(const SphConstants& k, ParticleState* state, bool first_step,
                                int threads) {
  ParticleState& s = *state;
  const float dt = k.time_step_s;
#pragma omp parallel for schedule(static) num_threads(threads)
  for (std::size_t n = 0; n < s.moving.size(); ++n) {
    const std::int32_t i = s.moving[n];
    const Float4 a = TotalAcceleration(s, i);
    s.last_acceleration[i] = a;
    if (first_step) continue;
    const Float4 v0 = s.velocity[i], x0 = s.position[i];
    // sphFluid.cl:1417-1418, both additions contracted; /s is the float reciprocal.
    Float4 v{Fma(a.x, dt, v0.x), Fma(a.y, dt, v0.y), Fma(a.z, dt, v0.z), v0.w};
    Float4 x{Fma(v.x * dt, k.inverse_scale, x0.x), Fma(v.y * dt, k.inverse_scale, x0.y),
             Fma(v.z * dt, k.inverse_scale, x0.z), x0.w};
    CorrectAtWalls(k, s, i, &x, &v);
    s.velocity[i] = v;
    s.position[i] = x;
  }
}

void MovePositionsLeapfrog(const SphConstants& k, ParticleState* state, int threads) {
  ParticleState& s = *state;
  const float dt = k.time_step_s;
#pragma omp parallel for schedule(static) num_threads(threads)
  for (std::size_t n = 0; n < s.moving.size(); ++n) {
    const std::int32_t i = s.moving[n];
    const Float4 x = s.position[i], v = s.velocity[i], a = s.last_acceleration[i];
    // sphFluid.cl:1455: both additions contracted.
    s.position[i] = {Fma(Fma(v.x, dt, a.x * dt * dt / 2.f), k.inverse_scale, x.x),
                     Fma(Fma(v.y, dt, a.y * dt * dt / 2.f), k.inverse_scale, x.y),
                     Fma(Fma(v.z, dt, a.z * dt * dt / 2.f), k.inverse_scale, x.z), x.w};
  }
}

void IntegrateLeapfrogVelocities(const SphConstants& k, ParticleState* state, bool first_step,
                                 int threads) {
  ParticleState& s = *state;
  const float dt = k.time_step_s;
#pragma omp parallel for schedule(static) num_threads(threads)
  for (std::size_t n = 0; n < s.moving.size(); ++n) {
    const std::int32_t i = s.moving[n];
    const Float4 a = TotalAcceleration(s, i), previous = s.last_acceleration[i];
    s.last_acceleration[i] = a;
    if (first_step) continue;
    const Float4 v0 = s.velocity[i];
    Float4 v{v0.x + (previous.x + a.x) * dt / 2.f, v0.y + (previous.y + a.y) * dt / 2.f,
             v0.z + (previous.z + a.z) * dt / 2.f, v0.w};
    Float4 x = s.position[i];
    CorrectAtWalls(k, s, i, &x, &v);
    s.velocity[i] = v;
    s.position[i] = x;
  }
}

}  // namespace owval::engine::internal
