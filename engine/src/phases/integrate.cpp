#include "phases/integrate.hpp"

#include "phases/walls.hpp"

namespace owval::engine::internal {
namespace {

Float4 TotalAcceleration(const ParticleState& s, const std::vector<Float4>& pressure_acceleration,
                         std::int32_t i) {
  const Float4 a = s.acceleration[i], ap = pressure_acceleration[i];
  return {a.x + ap.x, a.y + ap.y, a.z + ap.z, 0};
}

// The shared shape of both integrators' velocity update: a = a_i + a_p is remembered as the
// last acceleration; after the first step, `advance(a, a_last, &v, &x)` gives the new velocity
// and position, which the wall correction then adjusts.
template <typename Advance>
void IntegrateMoving(const SphConstants& k, const std::vector<Float4>& pressure_acceleration,
                     ParticleState* state, bool first_step, int threads, Advance advance) {
  ParticleState& s = *state;
#pragma omp parallel for schedule(static) num_threads(threads)
  for (std::size_t n = 0; n < s.moving.size(); ++n) {
    const std::int32_t i = s.moving[n];
    const Float4 a = TotalAcceleration(s, pressure_acceleration, i), last = s.last_acceleration[i];
    s.last_acceleration[i] = a;
    if (first_step) continue;
    Float4 v = s.velocity[i], x = s.position[i];
    advance(a, last, &v, &x);
    CorrectAtWalls(k, s, i, &x, &v);
    s.velocity[i] = v;
    s.position[i] = x;
  }
}

}  // namespace

void IntegrateSemiImplicitEuler(const SphConstants& k,
                                const std::vector<Float4>& pressure_acceleration,
                                ParticleState* state, bool first_step, int threads) {
  const float dt = k.time_step_s, to_cu = k.inverse_scale;
  IntegrateMoving(k, pressure_acceleration, state, first_step, threads,
                  [dt, to_cu](const Float4& a, const Float4&, Float4* v, Float4* x) {
                    // sphFluid.cl:1417-1418, both additions contracted; /s is the float
                    // reciprocal.
                    *v = {Fma(a.x, dt, v->x), Fma(a.y, dt, v->y), Fma(a.z, dt, v->z), v->w};
                    *x = {Fma(v->x * dt, to_cu, x->x), Fma(v->y * dt, to_cu, x->y),
                          Fma(v->z * dt, to_cu, x->z), x->w};
                  });
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

void IntegrateLeapfrogVelocities(const SphConstants& k,
                                 const std::vector<Float4>& pressure_acceleration,
                                 ParticleState* state, bool first_step, int threads) {
  const float dt = k.time_step_s;
  // Positions already moved (MovePositionsLeapfrog): only the velocity changes here.
  IntegrateMoving(k, pressure_acceleration, state, first_step, threads,
                  [dt](const Float4& a, const Float4& last, Float4* v, Float4*) {
                    *v = {v->x + (last.x + a.x) * dt / 2.f, v->y + (last.y + a.y) * dt / 2.f,
                          v->z + (last.z + a.z) * dt / 2.f, v->w};
                  });
}

}  // namespace owval::engine::internal
