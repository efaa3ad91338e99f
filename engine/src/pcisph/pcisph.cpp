#include "pcisph/pcisph.hpp"

#include <algorithm>
#include <cmath>

#include "phases/density.hpp"
#include "phases/forces.hpp"
#include "phases/integrate.hpp"
#include "phases/membranes.hpp"
#include "phases/pressure_force.hpp"
#include "phases/walls.hpp"
#include "state/initial_state.hpp"
#include "state/non_finite.hpp"
#include "state/state_io.hpp"

namespace owval::engine::internal {

Pcisph::Pcisph(const SiberneticConfig& config, const PhysicsConstants& constants,
               Integrator integrator, int threads)
    : k_(SphConstants::From(constants)),
      pcisph_(PcisphConstants::From(constants)),
      integrator_(integrator),
      threads_(threads),
      reference_equivalent_(constants.DifferencesFromDefaults().empty() &&
                            integrator == Integrator::kSemiImplicitEuler),
      grid_(config.box, k_),
      matter_(ElasticMatterOf(config, k_)) {
  LoadParticles(config, &state_);
  predicted_ = state_.position;
  predicted_density_.assign(state_.size(), 0);
  pressure_acceleration_.resize(state_.size());
  grid_.SetStatic(state_);
}

void Pcisph::Step() {
  const bool first = step_ == 0;
  clock_.Start();
  grid_.Refresh(&state_, threads_);
  if (integrator_ == Integrator::kLeapfrog && !first) MovePositionsLeapfrog(k_, &state_, threads_);
  clock_.Mark(kNeighbours);
  ComputeDensity(k_, &state_, threads_);
  clock_.Mark(kDensity);
  ComputeViscosityGravitySurfaceTension(k_, &state_, threads_);
  clock_.Mark(kForces);
  ResetPressure();
  AddSpringForces(k_, matter_, &state_, threads_);
  clock_.Mark(kSprings);
  const float short_range_pressure = k_.rest_density * pcisph_.delta;
  for (int iteration = 0; iteration < pcisph_.iterations; ++iteration) {
    PredictPositions();
    clock_.Mark(kPredictPositions);
    PredictDensity();
    clock_.Mark(kPredictDensity);
    CorrectPressure();
    clock_.Mark(kCorrectPressure);
    ComputePressureAcceleration(k_, state_, predicted_density_, short_range_pressure,
                                &pressure_acceleration_, threads_);
    clock_.Mark(kPressureAcceleration);
  }
  if (integrator_ == Integrator::kLeapfrog) {
    IntegrateLeapfrogVelocities(k_, pressure_acceleration_, &state_, first, threads_);
  } else {
    IntegrateSemiImplicitEuler(k_, pressure_acceleration_, &state_, first, threads_);
  }
  clock_.Mark(kIntegrate);
  if (!matter_.membranes.empty())
    InteractWithMembranes(k_, matter_, &state_, &membrane_scratch_, threads_);
  clock_.Mark(kMembranes);
  ++step_;
}

std::vector<float> Pcisph::Density() const { return output_density_.Of(k_, grid_, state_); }

void Pcisph::ResetPressure() {
  ParticleState& s = state_;
#pragma omp parallel for schedule(static) num_threads(threads_)
  for (std::size_t n = 0; n < s.active.size(); ++n) {
    const std::int32_t i = s.active[n];
    pressure_acceleration_[i] = {};
    s.pressure[i] = 0;
  }
}

void Pcisph::PredictPositions() {
  ParticleState& s = state_;
  const float position_step = k_.time_step_s * k_.inverse_scale;
#pragma omp parallel for schedule(static) num_threads(threads_)
  for (std::size_t n = 0; n < s.moving.size(); ++n) {
    const std::int32_t i = s.moving[n];
    const Float4 a = s.acceleration[i], ap = pressure_acceleration_[i], v = s.velocity[i],
                 x = s.position[i];
    const float vx = Fma(k_.time_step_s, a.x + ap.x, v.x),
                vy = Fma(k_.time_step_s, a.y + ap.y, v.y),
                vz = Fma(k_.time_step_s, a.z + ap.z, v.z);
    Float4 predicted{Fma(position_step, vx, x.x), Fma(position_step, vy, x.y),
                     Fma(position_step, vz, x.z), x.w};
    CorrectAtWalls(k_, s, i, &predicted, nullptr);  // positions only (sphFluid.cl:858-860)
    predicted_[i] = predicted;
  }
}

void Pcisph::PredictDensity() {
  ParticleState& s = state_;
#pragma omp parallel for schedule(static) num_threads(threads_)
  for (std::size_t n = 0; n < s.active.size(); ++n) {
    const std::int32_t i = s.active[n];
    const Float4 xi = predicted_[i];
    // Same neighbour list as x(t), distances from the predicted positions, summed in cu and
    // scaled to m⁶ after the sum.
    const float sum = Wpoly6Sum(k_.h2_cu, s.slots(i), [&](const Neighbour& slot) {
      const Float4& xj = predicted_[slot.index];
      const float dx = xi.x - xj.x, dy = xi.y - xj.y, dz = xi.z - xj.z;
      return Fma(dz, dz, Fma(dx, dx, dy * dy));  // sphFluid.cl:903-906
    });
    predicted_density_[i] = Wpoly6Density(k_, sum * k_.scale6);
  }
}

void Pcisph::CorrectPressure() {
  ParticleState& s = state_;
  // Only the increment is clamped: pressure grows within a step (sphFluid.cl:929-950).
#pragma omp parallel for schedule(static) num_threads(threads_)
  for (std::size_t n = 0; n < s.active.size(); ++n) {
    const std::int32_t i = s.active[n];
    s.pressure[i] += std::max(0.0f, pcisph_.delta * (predicted_density_[i] - k_.rest_density));
  }
}

void Pcisph::SaveState(std::string* out) const {
  StateWriter w(out);
  PutStateHeader(w, name(), state_.size(), step_);
  PutParticleState(w, state_);
  w.Put(predicted_), w.Put(predicted_density_), w.Put(pressure_acceleration_);
  w.Put(matter_.muscle_activation);
}

void Pcisph::RestoreState(const std::string& state, const std::string& source) {
  StateReader r(state, source);
  const std::size_t n = state_.size();
  const std::uint64_t steps = GetStateHeader(r, name(), n);
  GetParticleState(r, &state_);
  r.GetSized(&predicted_, n), r.GetSized(&predicted_density_, n);
  r.GetSized(&pressure_acceleration_, n);
  r.GetSized(&matter_.muscle_activation, std::size_t(kMuscles));
  if (!r.done()) r.Fail("bytes left after the state");
  step_ = std::size_t(steps);
}

Solver::NonFinite Pcisph::FirstNonFinite() const {
  return FirstNonFiniteOf(state_.position, state_.velocity, state_.moving);
}

}  // namespace owval::engine::internal
