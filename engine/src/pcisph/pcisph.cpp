#include "pcisph/pcisph.hpp"

#include <algorithm>
#include <cmath>

#include "phases/density.hpp"
#include "phases/forces.hpp"
#include "phases/integrate.hpp"
#include "phases/membranes.hpp"
#include "phases/walls.hpp"

namespace owval::engine::internal {
namespace {

Float4 ToFloat4(const Row4& r) { return {r[0], r[1], r[2], r[3]}; }

ElasticMatter ElasticMatterOf(const SiberneticConfig& config, const SphConstants& k) {
  ElasticMatter matter;
  matter.particle_count = config.elastic_count();
  // Rest lengths are stored in metres on load (owHelper.cpp:328-329).
  for (const Row4& c : config.connection)
    matter.springs.push_back({c[0], c[1] * k.scale, c[2], c[3]});
  matter.membranes = config.membranes;
  matter.membrane_index = config.particle_mem_index;
  return matter;
}

}  // namespace

Pcisph::Pcisph(const SiberneticConfig& config, const PhysicsConstants& constants,
               Integrator integrator, int threads)
    : k_(SphConstants::From(constants)),
      integrator_(integrator),
      threads_(threads),
      grid_(config.box, k_),
      matter_(ElasticMatterOf(config, k_)) {
  const std::size_t n = config.particle_count();
  state_.Resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    state_.position[i] = ToFloat4(config.position[i]);
    state_.velocity[i] = ToFloat4(config.velocity[i]);
    state_.predicted[i] = state_.position[i];
    if (!IsBoundary(state_.position[i].w)) state_.moving.push_back(std::int32_t(i));
  }
  grid_.SetStatic(state_);
}

void Pcisph::Step() {
  const bool first = step_ == 0;
  grid_.Refresh(&state_, threads_);
  if (integrator_ == Integrator::kLeapfrog && !first) MovePositionsLeapfrog(k_, &state_, threads_);
  ComputeDensity(k_, &state_, threads_);
  ComputeViscosityGravitySurfaceTension(k_, &state_, threads_);
  ResetPressure();
  AddSpringForces(k_, matter_, &state_, threads_);
  for (int iteration = 0; iteration < k_.pcisph_iterations; ++iteration) {
    PredictPositions();
    PredictDensity();
    CorrectPressure();
    ComputePressureAcceleration();
  }
  if (integrator_ == Integrator::kLeapfrog) {
    IntegrateLeapfrogVelocities(k_, &state_, first, threads_);
  } else {
    IntegrateSemiImplicitEuler(k_, &state_, first, threads_);
  }
  if (!matter_.membranes.empty())
    InteractWithMembranes(k_, matter_, &state_, &membrane_scratch_, threads_);
  ++step_;
}

std::vector<float> Pcisph::DensityOfAll() const {
  return internal::DensityOfAll(k_, grid_, state_);
}

void Pcisph::ResetPressure() {
  ParticleState& s = state_;
#pragma omp parallel for schedule(static) num_threads(threads_)
  for (std::size_t n = 0; n < s.active.size(); ++n) {
    const std::int32_t i = s.active[n];
    s.pressure_acceleration[i] = {};
    s.pressure[i] = 0;
  }
}

void Pcisph::PredictPositions() {
  ParticleState& s = state_;
  const float position_step = k_.time_step_s * k_.inverse_scale;
#pragma omp parallel for schedule(static) num_threads(threads_)
  for (std::size_t n = 0; n < s.moving.size(); ++n) {
    const std::int32_t i = s.moving[n];
    const Float4 a = s.acceleration[i], ap = s.pressure_acceleration[i], v = s.velocity[i],
                 x = s.position[i];
    const float vx = Fma(k_.time_step_s, a.x + ap.x, v.x),
                vy = Fma(k_.time_step_s, a.y + ap.y, v.y),
                vz = Fma(k_.time_step_s, a.z + ap.z, v.z);
    Float4 predicted{Fma(position_step, vx, x.x), Fma(position_step, vy, x.y),
                     Fma(position_step, vz, x.z), x.w};
    CorrectAtWalls(k_, s, i, &predicted, nullptr);  // positions only (sphFluid.cl:858-860)
    s.predicted[i] = predicted;
  }
}

void Pcisph::PredictDensity() {
  ParticleState& s = state_;
#pragma omp parallel for schedule(static) num_threads(threads_)
  for (std::size_t n = 0; n < s.active.size(); ++n) {
    const std::int32_t i = s.active[n];
    const Float4 xi = s.predicted[i];
    const Neighbour* slots = s.slots(i);
    float sum = 0;
    // Same neighbour list as x(t), distances from the predicted positions, summed in cu.
    for (int k = 0; k < kSlots && slots[k].index >= 0; ++k) {
      const Float4& xj = s.predicted[slots[k].index];
      const float dx = xi.x - xj.x, dy = xi.y - xj.y, dz = xi.z - xj.z;
      const float d2 = Fma(dz, dz, Fma(dx, dx, dy * dy));  // sphFluid.cl:903-906
      if (d2 < k_.h2_cu) {
        const float q = k_.h2_cu - d2;
        sum = Fma(q * q, q, sum);
      }
    }
    s.predicted_density[i] = k_.mass_wpoly6 * std::max(sum * k_.scale6, k_.hs6);
  }
}

void Pcisph::CorrectPressure() {
  ParticleState& s = state_;
  // Only the increment is clamped: pressure grows within a step (sphFluid.cl:929-950).
#pragma omp parallel for schedule(static) num_threads(threads_)
  for (std::size_t n = 0; n < s.active.size(); ++n) {
    const std::int32_t i = s.active[n];
    s.pressure[i] += std::max(0.0f, k_.delta * (s.predicted_density[i] - k_.rest_density));
  }
}

void Pcisph::ComputePressureAcceleration() {
  ParticleState& s = state_;
  const float quarter = k_.hs_m / 4;
#pragma omp parallel for schedule(static) num_threads(threads_)
  for (std::size_t n = 0; n < s.moving.size(); ++n) {
    const std::int32_t i = s.moving[n];
    const Float4 xi = s.position[i];
    const Neighbour* slots = s.slots(i);
    float sum[3] = {0, 0, 0};
    for (int k = 0; k < kSlots && slots[k].index >= 0; ++k) {
      const float r = slots[k].distance_m;
      if (!(r < k_.hs_m)) continue;
      const std::int32_t j = slots[k].index;
      // Below hS/4 a fixed short-range repulsion replaces the pressure term
      // (sphFluid.cl:1000-1010).
      const float t = r < quarter ? -(quarter - r) * (quarter - r) * 0.5f *
                                        (k_.rest_density * k_.delta) / s.predicted_density[j]
                                  : -(k_.hs_m - r) * (k_.hs_m - r) * 0.5f *
                                        (s.pressure[i] + s.pressure[j]) / s.predicted_density[j];
      const Float4 xj = s.position[j];  // direction from x(t), not x* (gotcha 7)
      sum[0] += t * ((xi.x - xj.x) * k_.scale) / r;
      sum[1] += t * ((xi.y - xj.y) * k_.scale) / r;
      sum[2] += t * ((xi.z - xj.z) * k_.scale) / r;
    }
    const float factor = k_.mass_grad_wspiky / s.predicted_density[i];
    s.pressure_acceleration[i] = {sum[0] * factor, sum[1] * factor, sum[2] * factor, 0};
  }
}

std::int64_t Pcisph::FirstNonFinite() const {
  for (std::int32_t i : state_.moving) {
    const Float4& x = state_.position[i];
    if (!std::isfinite(x.x) || !std::isfinite(x.y) || !std::isfinite(x.z)) return i;
  }
  return -1;
}

}  // namespace owval::engine::internal
