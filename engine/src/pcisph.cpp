#include "pcisph.hpp"

#include <algorithm>
#include <cmath>

namespace owval::engine::internal {
namespace {

constexpr int kMuscles = 96;

Float4 ToFloat4(const Row4& r) { return {r[0], r[1], r[2], r[3]}; }

}  // namespace

Pcisph::Pcisph(const SiberneticConfig& config, const PhysicsConstants& constants,
               Integrator integrator, int threads)
    : k_(SphConstants::From(constants)),
      integrator_(integrator),
      threads_(threads),
      grid_(config.box, k_),
      membranes_(config.membranes),
      membrane_index_(config.particle_mem_index),
      muscle_activation_(kMuscles, 0.0f) {
  const std::size_t n = config.particle_count();
  state_.Resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    state_.position[i] = ToFloat4(config.position[i]);
    state_.velocity[i] = ToFloat4(config.velocity[i]);
    state_.predicted[i] = state_.position[i];
    if (!IsBoundary(state_.position[i].w)) state_.moving.push_back(std::int32_t(i));
  }
  elastic_count_ = config.elastic_count();
  // Rest lengths are stored in metres on load (owHelper.cpp:328-329).
  for (const Row4& c : config.connection)
    connections_.push_back({c[0], c[1] * k_.scale, c[2], c[3]});
  membrane_correction_.resize(n);
  is_active_.assign(n, 0);
  grid_.SetStatic(state_);
}

void Pcisph::Step() {
  FindNeighbours();
  if (integrator_ == Integrator::kLeapfrog) MovePositionsLeapfrog();
  ComputeDensity();
  ComputeForces();
  ComputeElasticForces();
  for (int iteration = 0; iteration < k_.pcisph_iterations; ++iteration) {
    PredictPositions();
    PredictDensity();
    CorrectPressure();
    ComputePressureAcceleration();
  }
  if (integrator_ == Integrator::kLeapfrog) {
    IntegrateLeapfrogVelocities();
  } else {
    Integrate();
  }
  if (!membranes_.empty()) InteractWithMembranes();
  ++step_;
}

void Pcisph::FindNeighbours() {
  ParticleState& s = state_;
  grid_.UpdateMoving(s);
  const auto& moving = s.moving;
#pragma omp parallel for schedule(static) num_threads(threads_)
  for (std::size_t n = 0; n < moving.size(); ++n)
    grid_.FindNeighbours(s, moving[n], s.slots(moving[n]));
  // Active boundary particles: those some moving particle lists as a neighbour.
  for (std::int32_t b : s.active) is_active_[b] = 0;
  s.active = moving;
  for (std::int32_t i : moving) is_active_[i] = 1;
  for (std::int32_t i : moving) {
    const Neighbour* slots = s.slots(i);
    for (int k = 0; k < kSlots && slots[k].index >= 0; ++k) {
      const std::int32_t j = slots[k].index;
      if (!is_active_[j]) {
        is_active_[j] = 1;
        s.active.push_back(j);
      }
    }
  }
  const std::size_t first_boundary = moving.size();
#pragma omp parallel for schedule(static) num_threads(threads_)
  for (std::size_t n = first_boundary; n < s.active.size(); ++n)
    grid_.FindNeighbours(s, s.active[n], s.slots(s.active[n]));
}

float Pcisph::DensitySum(const Neighbour* slots) const {
  float sum = 0;
  for (int k = 0; k < kSlots && slots[k].index >= 0; ++k) {
    const float r2 = slots[k].distance_m * slots[k].distance_m;
    if (r2 < k_.hs2_m2) {
      const float q = k_.hs2_m2 - r2;
      sum = Fma(q * q, q, sum);  // sphFluid.cl:499
    }
  }
  return sum;
}

void Pcisph::ComputeDensity() {
  ParticleState& s = state_;
  // No self term: the sum is floored at hS⁶, what a self term would add (sphFluid.cl:473-510).
#pragma omp parallel for schedule(static) num_threads(threads_)
  for (std::size_t n = 0; n < s.active.size(); ++n) {
    const std::int32_t i = s.active[n];
    s.density[i] = k_.mass_wpoly6 * std::max(DensitySum(s.slots(i)), k_.hs6);
  }
}

void Pcisph::ComputeForces() {
  ParticleState& s = state_;
#pragma omp parallel for schedule(static) num_threads(threads_)
  for (std::size_t n = 0; n < s.active.size(); ++n) {
    const std::int32_t i = s.active[n];
    s.pressure_acceleration[i] = {};
    s.pressure[i] = 0;
    if (IsBoundary(s.position[i].w)) {
      s.acceleration[i] = {};
      continue;
    }
    const Float4 xi = s.position[i], vi = s.velocity[i];
    float viscosity[3] = {0, 0, 0}, surface_tension[3] = {0, 0, 0};
    const Neighbour* slots = s.slots(i);
    for (int k = 0; k < kSlots && slots[k].index >= 0; ++k) {
      const float r = slots[k].distance_m;
      if (!(r < k_.hs_m)) continue;
      const std::int32_t j = slots[k].index;
      const Float4 xj = s.position[j];
      // Viscosity: 1e-5 between worm body and agar, 1e-4 otherwise; a boundary's velocity slot
      // holds its normal, so its velocity counts as zero (sphFluid.cl:570-625).
      const bool wb_agar = (IsWormBody(xi.w) && IsAgar(xj.w)) || (IsAgar(xi.w) && IsWormBody(xj.w));
      const float c = wb_agar ? 1.0e-5f : 1.0e-4f;
      const Float4 vj = IsBoundary(xj.w) ? Float4{} : s.velocity[j];
      const float dv[3] = {vj.x - vi.x, vj.y - vi.y, vj.z - vi.z};
      for (int a = 0; a < 3; ++a) viscosity[a] += ((c * dv[a]) * (k_.hs_m - r)) / 1000.0f;
      // Cohesion with every neighbour, walls included, on cu differences (sphFluid.cl:645-655).
      const float r2 = r * r;
      const float q = k_.hs2_m2 - r2;
      const float coefficient = k_.surface_tension * (q * q * q);
      const float dx[3] = {xi.x - xj.x, xi.y - xj.y, xi.z - xj.z};
      for (int a = 0; a < 3; ++a) surface_tension[a] = Fma(coefficient, dx[a], surface_tension[a]);
    }
    const float viscosity_scale = (1.5f * k_.mass_lap_wviscosity) / s.density[i];
    float a[3];
    for (int d = 0; d < 3; ++d)
      a[d] = viscosity[d] * viscosity_scale + k_.gravity[d] + surface_tension[d] / k_.mass_kg;
    s.acceleration[i] = {a[0], a[1], a[2], 0};
  }
}

void Pcisph::ComputeElasticForces() {
  ParticleState& s = state_;
#pragma omp parallel for schedule(static) num_threads(threads_)
  for (std::size_t e = 0; e < elastic_count_; ++e) {
    const Float4 xe = s.position[e];
    // Each spring adds straight into the particle's acceleration, in slot order
    // (sphFluid.cl:726-739): the order of the float additions is part of the result.
    float a[3] = {s.acceleration[e].x, s.acceleration[e].y, s.acceleration[e].z};
    for (int slot = 0; slot < 32; ++slot) {
      const Float4& c = connections_[e * 32 + slot];
      if (c.x < 0) break;  // the first empty partner ends the list
      const std::int32_t j = static_cast<std::int32_t>(c.x);
      const Float4 xj = s.position[j];
      const float d[3] = {(xe.x - xj.x) * k_.scale, (xe.y - xj.y) * k_.scale,
                          (xe.z - xj.z) * k_.scale};
      const float r = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      if (r == 0) continue;
      const float stretch = r - c.y;
      float inward[3];  // −r̂
      for (int k = 0; k < 3; ++k) inward[k] = -(d[k] / r);
      // Full stiffness only between two worm-body particles; every other spring is four times
      // softer (sphFluid.cl:723-731).
      if (IsWormBody(xe.w) && IsWormBody(xj.w)) {
        for (int k = 0; k < 3; ++k)
          a[k] = Fma(inward[k] * stretch, k_.elasticity_coefficient, a[k]);
      } else {
        for (int k = 0; k < 3; ++k)
          a[k] = Fma(inward[k] * stretch * k_.elasticity_coefficient,
                     k_.non_worm_body_spring_factor, a[k]);
      }
      // Muscles pull along the spring with signal·F, already an acceleration (sphFluid.cl:734-741).
      const int muscle = static_cast<int>(c.z);
      if (muscle >= 1 && muscle <= kMuscles && muscle_activation_[muscle - 1] > 0) {
        const float signal = muscle_activation_[muscle - 1];
        for (int k = 0; k < 3; ++k) a[k] = Fma(inward[k] * signal, k_.max_muscle_force, a[k]);
      }
    }
    s.acceleration[e].x = a[0];
    s.acceleration[e].y = a[1];
    s.acceleration[e].z = a[2];
  }
}

void Pcisph::CorrectAtWalls(std::int32_t i, Float4* x, Float4* v) const {
  const ParticleState& s = state_;
  Float4 normal{};
  float weight_sum = 0, weighted_depth = 0;
  const Neighbour* slots = s.slots(i);
  for (int k = 0; k < kSlots; ++k) {
    const std::int32_t b = slots[k].index;
    if (b < 0 || !IsBoundary(s.position[b].w)) continue;
    const Float4& xb = s.position[b];
    const float dx = x->x - xb.x, dy = x->y - xb.y, dz = x->z - xb.z;
    const float dist = std::sqrt(Fma(dz, dz, Fma(dy, dy, dx * dx)));  // sphFluid.cl:786-789
    const float w = std::max(0.0f, (k_.r0_cu - dist) / k_.r0_cu);     // [IAGT10] eq. 10
    const Float4& nb = s.velocity[b];  // a boundary's velocity slot holds its wall normal
    normal.x = Fma(nb.x, w, normal.x);
    normal.y = Fma(nb.y, w, normal.y);
    normal.z = Fma(nb.z, w, normal.z);
    normal.w = Fma(nb.w, w, normal.w);  // the 4th component takes part in the normalisation
    weight_sum += w;
    weighted_depth = Fma(w, k_.r0_cu - dist, weighted_depth);
  }
  // OpenCL's dot() as PoCL's library computes it, unfused: (x² + y²) + (z² + w²).
  float length =
      (normal.x * normal.x + normal.y * normal.y) + (normal.z * normal.z + normal.w * normal.w);
  if (length == 0) return;
  length = std::sqrt(length);
  x->x += normal.x / length * weighted_depth / weight_sum;  // [IAGT10] eq. 11
  x->y += normal.y / length * weighted_depth / weight_sum;
  x->z += normal.z / length * weighted_depth / weight_sum;
  if (!v) return;
  // Remove the velocity into the wall along the (unnormalised) normal, then friction 0.99.
  const float into = Fma(normal.z, v->z, Fma(normal.x, v->x, normal.y * v->y));
  if (into < 0) {
    v->x = Fma(-normal.x, into, v->x);
    v->y = Fma(-normal.y, into, v->y);
    v->z = Fma(-normal.z, into, v->z);
    v->x *= 0.99f;
    v->y *= 0.99f;
    v->z *= 0.99f;
    v->w *= 0.99f;
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
    CorrectAtWalls(i, &predicted, nullptr);  // positions only (sphFluid.cl:858-860)
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

void Pcisph::Integrate() {
  ParticleState& s = state_;
  const bool first = step_ == 0;
#pragma omp parallel for schedule(static) num_threads(threads_)
  for (std::size_t n = 0; n < s.moving.size(); ++n) {
    const std::int32_t i = s.moving[n];
    const Float4 a0 = s.acceleration[i], ap = s.pressure_acceleration[i];
    const Float4 a{a0.x + ap.x, a0.y + ap.y, a0.z + ap.z, 0};
    s.last_acceleration[i] = a;
    if (first) continue;  // nothing moves at step 0 (sphFluid.cl:1368-1373)
    Float4 v = s.velocity[i];
    v = {Fma(a.x, k_.time_step_s, v.x), Fma(a.y, k_.time_step_s, v.y),
         Fma(a.z, k_.time_step_s, v.z), v.w};  // sphFluid.cl:1417-1418
    const Float4 x0 = s.position[i];
    Float4 x{Fma(v.x * k_.time_step_s, k_.inverse_scale, x0.x),
             Fma(v.y * k_.time_step_s, k_.inverse_scale, x0.y),
             Fma(v.z * k_.time_step_s, k_.inverse_scale, x0.z), x0.w};
    CorrectAtWalls(i, &x, &v);
    s.velocity[i] = v;
    s.position[i] = x;
  }
}

void Pcisph::MovePositionsLeapfrog() {
  if (step_ == 0) return;
  ParticleState& s = state_;
  const float dt = k_.time_step_s;
#pragma omp parallel for schedule(static) num_threads(threads_)
  for (std::size_t n = 0; n < s.moving.size(); ++n) {
    const std::int32_t i = s.moving[n];
    const Float4 x = s.position[i], v = s.velocity[i], a = s.last_acceleration[i];
    // sphFluid.cl:1455: both additions contracted.
    s.position[i] = {Fma(Fma(v.x, dt, a.x * dt * dt / 2.f), k_.inverse_scale, x.x),
                     Fma(Fma(v.y, dt, a.y * dt * dt / 2.f), k_.inverse_scale, x.y),
                     Fma(Fma(v.z, dt, a.z * dt * dt / 2.f), k_.inverse_scale, x.z), x.w};
  }
}

void Pcisph::IntegrateLeapfrogVelocities() {
  ParticleState& s = state_;
  const float dt = k_.time_step_s;
#pragma omp parallel for schedule(static) num_threads(threads_)
  for (std::size_t n = 0; n < s.moving.size(); ++n) {
    const std::int32_t i = s.moving[n];
    const Float4 a0 = s.acceleration[i], ap = s.pressure_acceleration[i];
    const Float4 a{a0.x + ap.x, a0.y + ap.y, a0.z + ap.z, 0};
    const Float4 previous = s.last_acceleration[i];
    s.last_acceleration[i] = a;
    if (step_ == 0) continue;
    Float4 v = s.velocity[i];
    v = {v.x + (previous.x + a.x) * dt / 2.f, v.y + (previous.y + a.y) * dt / 2.f,
         v.z + (previous.z + a.z) * dt / 2.f, v.w};
    Float4 x = s.position[i];
    CorrectAtWalls(i, &x, &v);
    s.velocity[i] = v;
    s.position[i] = x;
  }
}

std::vector<float> Pcisph::DensityOfAll() const {
  std::vector<float> density(state_.size());
  std::vector<Neighbour> slots(kSlots);
  for (std::size_t i = 0; i < state_.size(); ++i) {
    if (is_active_[i]) {
      density[i] = state_.density[i];
      continue;
    }
    grid_.FindNeighbours(state_, std::int32_t(i), slots.data());
    density[i] = k_.mass_wpoly6 * std::max(DensitySum(slots.data()), k_.hs6);
  }
  return density;
}

std::int64_t Pcisph::FirstNonFinite() const {
  for (std::int32_t i : state_.moving) {
    const Float4& x = state_.position[i];
    if (!std::isfinite(x.x) || !std::isfinite(x.y) || !std::isfinite(x.z)) return i;
  }
  return -1;
}

}  // namespace owval::engine::internal
