#pragma once
// Predictive-corrective incompressible SPH as Sibernetic computes it (src/sphFluid.cl and
// src/owPhysicsFluidSimulator.cpp at commit 8d2df73; the behaviour, quirks included, is written
// down in shared/docs/sibernetic_physics.md).
//
//   [SP09]  B. Solenthaler, R. Pajarola. Predictive-corrective incompressible SPH.
//           ACM Transactions on Graphics 28(3), 40:1-40:6, 2009.
//   [IAGT10] M. Ihmsen, N. Akinci, M. Gissler, M. Teschner. Boundary handling and adaptive
//           time-stepping for PCISPH. VRIPHYS 2010, pp. 79-88.
//
// One step is a pipeline of named phases over shared ParticleState:
//   neighbours → density → forces (viscosity, surface tension, gravity) → elastic
//   → pressure iterations {predict, predicted density, pressure, pressure force}
//   → integrate → membranes.
// Only moving particles and the boundary particles in their neighbour lists are computed;
// boundary particles elsewhere influence nobody, so the result is the same as computing all.
#include <vector>

#include "neighbour_grid.hpp"
#include "owval/engine/config.hpp"
#include "owval/engine/run.hpp"
#include "particle_state.hpp"
#include "sph_constants.hpp"

namespace owval::engine::internal {

class Pcisph {
 public:
  Pcisph(const SiberneticConfig& config, const PhysicsConstants& constants, Integrator integrator,
         int threads);

  // Advances one step. Step 0 integrates nothing (Sibernetic's iterationCount == 0), but the
  // membrane pass already moves liquid.
  void Step();
  std::size_t steps_done() const { return step_; }
  const ParticleState& state() const { return state_; }
  // Density of every particle at the current positions (boundary ones far from the action
  // included), for output; the step itself needs only the active ones.
  std::vector<float> DensityOfAll() const;
  // Muscle activations (96 values, Sibernetic's signal vector), used by the next step.
  std::vector<float>& muscle_activation() { return muscle_activation_; }
  // Index of the first moving particle with a non-finite position, or -1.
  std::int64_t FirstNonFinite() const;

 private:
  void FindNeighbours();
  void MovePositionsLeapfrog();
  void ComputeDensity();
  void ComputeForces();
  void ComputeElasticForces();
  void PredictPositions();
  void PredictDensity();
  void CorrectPressure();
  void ComputePressureAcceleration();
  void Integrate();
  void IntegrateLeapfrogVelocities();
  void InteractWithMembranes();

  // Ihmsen et al. 2010 §3.2 wall correction of a new position (and velocity when given) from the
  // boundary particles in i's x(t) neighbour list.
  void CorrectAtWalls(std::int32_t i, Float4* position, Float4* velocity) const;
  float DensitySum(const Neighbour* slots) const;

  SphConstants k_;
  Integrator integrator_;
  int threads_;
  ParticleState state_;
  NeighbourGrid grid_;
  std::vector<Float4>
      connections_;  // 32 per elastic particle: partner, rest length (m), muscle, extra
  std::size_t elastic_count_ = 0;
  std::vector<std::array<int, 3>> membranes_;
  std::vector<int> membrane_index_;  // 7 per elastic particle
  std::vector<Float4> membrane_correction_;
  std::vector<float> muscle_activation_;
  std::vector<char> is_active_;
  std::size_t step_ = 0;
};

}  // namespace owval::engine::internal
