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
// Neighbours, density, forces, springs, walls, the pressure acceleration, integrators and
// membranes are shared phases (neighbours/, phases/); the prediction-correction loop, its state
// (x*, ρ*, a_p) and its constants (δ, iteration count) make this scheme PCISPH and live here.
// Only moving particles and the boundary particles in their neighbour lists are computed;
// boundary particles elsewhere influence nobody, so the result is the same as computing all.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "kernels/sph_constants.hpp"
#include "neighbours/neighbour_grid.hpp"
#include "owval/engine/config.hpp"
#include "owval/engine/run.hpp"
#include "owval/engine/solver.hpp"
#include "pcisph/pcisph_constants.hpp"
#include "phase_clock.hpp"
#include "phases/density.hpp"
#include "state/elastic_matter.hpp"
#include "state/particle_state.hpp"

namespace owval::engine::internal {

class Pcisph final : public Solver {
 public:
  Pcisph(const SiberneticConfig& config, const PhysicsConstants& constants, Integrator integrator,
         int threads);

  // Advances one step. Step 0 integrates nothing (Sibernetic's iterationCount == 0), but the
  // membrane pass already moves liquid.
  void Step() override;
  std::size_t steps_done() const override { return step_; }
  std::string name() const override { return "pcisph"; }
  int threads() const override { return threads_; }
  // Sibernetic's defaults with its default (semi-implicit Euler) integrator.
  bool reference_equivalent() const override { return reference_equivalent_; }
  std::span<const Float4> positions() const override { return state_.position; }
  std::span<const Float4> velocities() const override { return state_.velocity; }
  // Density of every particle (boundary ones far from the action included), for output.
  std::vector<float> Density() const override;
  std::span<const float> pressure() const override { return state_.pressure; }
  // Muscle activations (96 values, Sibernetic's signal vector), used by the next step.
  std::span<float> muscle_activation() override { return matter_.muscle_activation; }
  NonFinite FirstNonFinite() const override;
  void EnablePhaseTiming() override { clock_.Enable(); }
  std::vector<PhaseTime> phase_seconds() const override { return clock_.seconds(); }
  // Everything Step() reads: the particle state (x, v, a, last a, ρ, p, neighbour lists, active
  // set), x*, ρ*, a_p, the muscle activations and the step counter. The neighbour grid is not
  // saved: Refresh rebuilds it from the positions at the start of every step.
  void SaveState(std::string* out) const override;
  void RestoreState(const std::string& state, const std::string& source) override;
  bool can_checkpoint() const override { return true; }

  const ParticleState& state() const { return state_; }

 private:
  // [SP09] §3: p = 0 and a_p = 0 before the pressure loop (sphFluid.cl:664-666).
  void ResetPressure();
  // x* = x + dt/s·(v + dt·(a + a_p)), pushed out of the walls (positions only).
  void PredictPositions();
  // ρ* from x*, over the x(t) neighbour lists, summed in cu.
  void PredictDensity();
  // p += max(0, δ·(ρ* − ρ0)): only the increment is clamped.
  void CorrectPressure();

  // The phases of Step(), in order, for the per-phase profile.
  enum Phase {
    kNeighbours,
    kDensity,
    kForces,
    kSprings,
    kPredictPositions,
    kPredictDensity,
    kCorrectPressure,
    kPressureAcceleration,
    kIntegrate,
    kMembranes,
    kPhaseCount
  };

  SphConstants k_;
  PcisphConstants pcisph_;
  Integrator integrator_;
  int threads_;
  bool reference_equivalent_;
  ParticleState state_;
  NeighbourGrid grid_;
  ElasticMatter matter_;
  // PCISPH's own per-particle quantities: x* (cu), ρ* (kg/m³) and the pressure acceleration a_p
  // (m/s²) of the pressure loop.
  std::vector<Float4> predicted_;
  std::vector<float> predicted_density_;
  std::vector<Float4> pressure_acceleration_;
  std::vector<Float4> membrane_scratch_;
  mutable internal::OutputDensity output_density_;  // for Density()
  std::size_t step_ = 0;
  PhaseClock<kPhaseCount> clock_{{"neighbours", "density", "forces", "springs", "predict_positions",
                                  "predict_density", "correct_pressure", "pressure_acceleration",
                                  "integrate", "membranes"}};
};

}  // namespace owval::engine::internal
