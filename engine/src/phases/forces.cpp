#include "phases/forces.hpp"

#include <cmath>

#include "kernels/kernels.hpp"

namespace owval::engine::internal {
namespace {

// Viscosity coefficient of a pair: 1e-5 between worm body and agar, 1e-4 for every other pair
// (sphFluid.cl:580-625).
float ViscosityCoefficient(float type_i, float type_j) {
  const bool body_agar =
      (IsWormBody(type_i) && IsAgar(type_j)) || (IsAgar(type_i) && IsWormBody(type_j));
  return body_agar ? 1.0e-5f : 1.0e-4f;
}

// Viscosity, gravity and surface tension of one moving particle.
Float4 NonPressureAcceleration(const SphConstants& k, const ParticleState& s, std::int32_t i) {
  const Float4 xi = s.position[i], vi = s.velocity[i];
  float viscosity[3] = {0, 0, 0}, surface_tension[3] = {0, 0, 0};
  const Neighbour* slots = s.slots(i);
  for (int n = 0; n < kSlots && slots[n].index >= 0; ++n) {
    const float r = slots[n].distance_m;
    if (!(r < k.hs_m)) continue;
    const std::int32_t j = slots[n].index;
    const Float4 xj = s.position[j];
    const float c = ViscosityCoefficient(xi.w, xj.w);
    // A boundary's velocity slot holds its wall normal: its velocity counts as zero.
    const Float4 vj = IsBoundary(xj.w) ? Float4{} : s.velocity[j];
    const float dv[3] = {vj.x - vi.x, vj.y - vi.y, vj.z - vi.z};
    // ∇²Wviscosity's shape; its coefficient is in mass_lap_wviscosity.
    const float laplacian = ViscosityLaplacianShape(k.hs_m, r);
    for (int a = 0; a < 3; ++a) viscosity[a] += ((c * dv[a]) * laplacian) / 1000.0f;
    // Cohesion weighs the offset by Wpoly6's shape (sphFluid.cl:645-655).
    const float coefficient = k.surface_tension * Wpoly6Shape(k.hs2_m2, r * r);
    const float dx[3] = {xi.x - xj.x, xi.y - xj.y, xi.z - xj.z};
    for (int a = 0; a < 3; ++a) surface_tension[a] = Fma(coefficient, dx[a], surface_tension[a]);
  }
  // Note ρ_j does not appear; the viscosity sum is scaled by 1.5·m∇²W/ρ_i (sphFluid.cl:657).
  const float viscosity_scale = (1.5f * k.mass_lap_wviscosity) / s.density[i];
  float a[3];
  for (int d = 0; d < 3; ++d)
    a[d] = viscosity[d] * viscosity_scale + k.gravity[d] + surface_tension[d] / k.mass_kg;
  return {a[0], a[1], a[2], 0};
}

// Sibernetic's force kernel overwrites the type code of an agar particle with a worm-body
// neighbour within hS by 2.32 (sphFluid.cl:592-595). Still agar, so no force changes, but the
// membranes' distance uses type codes and the value persists. Done after the parallel pass, in
// which every read of a type code sees the old value, as the forces do.
void MarkAgarTouchingWormBody(const SphConstants& k, ParticleState* state) {
  ParticleState& s = *state;
  for (std::int32_t i : s.moving) {
    if (!IsAgar(s.position[i].w)) continue;
    const Neighbour* slots = s.slots(i);
    for (int n = 0; n < kSlots && slots[n].index >= 0; ++n) {
      if (slots[n].distance_m < k.hs_m && IsWormBody(s.position[slots[n].index].w)) {
        s.position[i].w = 2.32f;
        break;
      }
    }
  }
}

}  // namespace

void ComputeViscosityGravitySurfaceTension(const SphConstants& k, ParticleState* state,
                                           int threads) {
  ParticleState& s = *state;
#pragma omp parallel for schedule(static) num_threads(threads)
  for (std::size_t n = 0; n < s.active.size(); ++n) {
    const std::int32_t i = s.active[n];
    s.acceleration[i] = IsBoundary(s.position[i].w) ? Float4{} : NonPressureAcceleration(k, s, i);
  }
  MarkAgarTouchingWormBody(k, &s);
}

void AddSpringForces(const SphConstants& k, const ElasticMatter& matter, ParticleState* state,
                     int threads) {
  ParticleState& s = *state;
#pragma omp parallel for schedule(static) num_threads(threads)
  for (std::size_t e = 0; e < matter.particle_count; ++e) {
    const Float4 xe = s.position[e];
    // Each spring adds straight into the particle's acceleration, in slot order
    // (sphFluid.cl:726-739): the order of the float additions is part of the result.
    float a[3] = {s.acceleration[e].x, s.acceleration[e].y, s.acceleration[e].z};
    for (int slot = 0; slot < kSpringSlots; ++slot) {
      const Float4& c = matter.springs[e * kSpringSlots + slot];
      if (c.x < 0) break;  // the first empty partner ends the list
      const std::int32_t j = static_cast<std::int32_t>(c.x);
      const Float4 xj = s.position[j];
      const float d[3] = {(xe.x - xj.x) * k.scale, (xe.y - xj.y) * k.scale,
                          (xe.z - xj.z) * k.scale};
      const float r = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      if (r == 0) continue;
      const float stretch = r - c.y;  // metres
      float inward[3];                // −r̂
      for (int n = 0; n < 3; ++n) inward[n] = -(d[n] / r);
      // Full stiffness only between two worm-body particles; every other spring is four times
      // softer (sphFluid.cl:723-731).
      if (IsWormBody(xe.w) && IsWormBody(xj.w)) {
        for (int n = 0; n < 3; ++n) a[n] = Fma(inward[n] * stretch, k.elasticity_coefficient, a[n]);
      } else {
        for (int n = 0; n < 3; ++n)
          a[n] = Fma(inward[n] * stretch * k.elasticity_coefficient, k.non_worm_body_spring_factor,
                     a[n]);
      }
      // Muscles pull along the spring with signal·F, already an acceleration (sphFluid.cl:734-741).
      const int muscle = static_cast<int>(c.z);
      if (muscle >= 1 && muscle <= kMuscles && matter.muscle_activation[muscle - 1] > 0) {
        const float signal = matter.muscle_activation[muscle - 1];
        for (int n = 0; n < 3; ++n) a[n] = Fma(inward[n] * signal, k.max_muscle_force, a[n]);
      }
    }
    s.acceleration[e] = {a[0], a[1], a[2], s.acceleration[e].w};
  }
}

}  // namespace owval::engine::internal
