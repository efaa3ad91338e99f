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
//   neighbours → density → non-pressure forces → springs
//   → 3 × {predict positions, predicted density, correct pressure, pressure acceleration}
//   → integrate → membranes.
// Neighbours, density, forces, springs, walls, integrators and membranes are shared phases
// (neighbours/, phases/); the pressure loop is what makes this scheme PCISPH and lives here.
// Only moving particles and the boundary particles in their neighbour lists are computed;
// boundary particles elsewhere influence nobody, so the result is the same as computing all.
#include <cstdint>
#include <vector>

#include "kernels/sph_constants.hpp"
#include "neighbours/neighbour_grid.hpp"
#include "owval/engine/config.hpp"
#include "owval/engine/run.hpp"
#include "state/elastic_matter.hpp"
#include "state/particle_state.hpp"

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
  // Density of every particle (boundary ones far from the action included), for output.
  std::vector<float> DensityOfAll() const;
  // Muscle activations (96 values, Sibernetic's signal vector), used by the next step.
  std::vector<float>& muscle_activation() { return matter_.muscle_activation; }
  // Index of the first moving particle with a non-finite position, or -1.
  std::int64_t FirstNonFinite() const;

 private:
  // [SP09] §3: p = 0 and a_p = 0 before the pressure loop (sphFluid.cl:664-666).
  void ResetPressure();
  // x* = x + dt/s·(v + dt·(a + a_p)), pushed out of the walls (positions only).
  void PredictPositions();
  // ρ* from x*, over the x(t) neighbour lists, summed in cu.
  void PredictDensity();
  // p += max(0, δ·(ρ* − ρ0)): only the increment is clamped.
  void CorrectPressure();
  // a_p from p and ρ*, with x(t) distances and directions; a fixed short-range repulsion below
  // hS/4.
  void ComputePressureAcceleration();

  SphConstants k_;
  Integrator integrator_;
  int threads_;
  ParticleState state_;
  NeighbourGrid grid_;
  ElasticMatter matter_;
  std::vector<Float4> membrane_scratch_;
  std::size_t step_ = 0;
};

}  // namespace owval::engine::internal
