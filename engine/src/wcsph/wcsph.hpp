#pragma once
// Weakly compressible SPH after the ultraballpit design (docs/wcsph.md), over the liquid and
// boundary particles of a Sibernetic configuration:
//   kernel      Wendland C2, support 2h, h = h_factor × spacing [W95] (kernels/wendland_c2.hpp)
//   density     continuity equation dρ_i/dt = Σ_j m (v_i − v_j)·∇_i W_ij [Mon92], plus δ-SPH
//               diffusion [MC09] from the step's input densities (DensityDiffusionPair)
//   pressure    Tait: p = c_s² ρ0/γ ((ρ/ρ0)^γ − 1) [Mon94], c_s = max(10 √(2 g H), c_min)
//   forces      −Σ m (p_i/ρ_i² + p_j/ρ_j²) ∇_i W_ij + Monaghan's artificial viscosity + g
//   walls       dynamic boundary particles [CGD07]: they keep still, their density follows the
//               continuity equation (never below ρ0) and their Tait pressure pushes the liquid
//   integrator  velocity Verlet, kick-drift-kick; the drift uses XSPH velocities [Mon89] and
//               moves the density with the positions: ρ^{n+1} = ρ^n + dt Dρ(x^n, v^{n+1/2}), the
//               forces at n+1 then see ρ^{n+1}. (Kicking ρ with v instead, half steps at a time,
//               makes the acoustic pair (ρ, v) a forward Euler step: |amplification|² = 1 +
//               (ω dt)², a slow growth that only δ-SPH and viscosity held back at CFL 0.2.)
//   time step   dt_safe = CFL · min(h/(c_s + |v|max), √(h/|a|max)); optimistic: try
//               1.5 dt_safe from a checkpoint, roll back and retry at dt_safe when the maximum
//               |ρ − ρ0|/ρ0 exceeds 3%, then 10 steps at dt_safe
//   memory      particles reordered along a Morton curve of their cells every 20 steps; the
//               configuration's row order is kept for every output
// Each technique is a switch of PhysicsConstants::Wcsph (--set wcsph_...), named in parameters().
//
// One Step() advances the constants' time_step_s of simulated time (the nominal step) with as
// many adaptive sub-steps as it takes, the last one shortened to land on it: frames recorded every
// log_step steps are at fixed simulated times. Step 0 moves nothing (it evaluates the initial
// state), so the frame after step k is at k · time_step_s, as Run labels it.
//
//   [W95]   H. Wendland. Adv. Comput. Math. 4 (1995) 389-396.
//   [Mon92] J. J. Monaghan. Smoothed particle hydrodynamics. ARA&A 30 (1992) 543-574.
//   [Mon94] J. J. Monaghan. Simulating free surface flows with SPH. JCP 110 (1994) 399-406.
//   [Mon89] J. J. Monaghan. On the problem of penetration in particle methods. JCP 82 (1989) 1-15.
//   [MC09]  D. Molteni, A. Colagrossi. A simple procedure to improve the pressure evaluation in
//           hydrodynamic context using the SPH. Comput. Phys. Commun. 180 (2009) 861-872.
//   [CGD07] A. J. C. Crespo, M. Gómez-Gesteira, R. A. Dalrymple. Boundary conditions generated
//           by dynamic particles in SPH methods. CMC 5(3) (2007) 173-184.
#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "kernels/wendland_c2.hpp"
#include "neighbours/cell_list.hpp"
#include "owval/engine/solver.hpp"
#include "phase_clock.hpp"

namespace owval::engine::internal {

// δ-SPH's pair term [MC09 eq. 6] without its factor 2 δ h c_s: the contribution of particle j to
// the density rate of particle i,
//   (ρ_i − ρ_j) · (r_ij · ∇_i W_ij) / |r_ij|² · V_j,   r_ij = x_i − x_j, V_j = m/ρ_j.
// With r_ij pointing from j to i, r_ij · ∇_i W_ij = r dW/dr < 0, so a particle denser than its
// neighbours loses density: diffusion. [MC09] writes the same term with r_ji = x_j − x_i and
// (ρ_j − ρ_i); mixing the two conventions (ρ_j − ρ_i with r_ij) flips the sign and turns the
// diffusion into an anti-diffusion that blows up (the ultraballpit record's pitfall).
// gradient_over_r is dW/dr / r, so r_ij · ∇_i W_ij = gradient_over_r · r².
inline float DensityDiffusionPair(float rho_i, float rho_j, float gradient_over_r, float volume_j) {
  return (rho_i - rho_j) * gradient_over_r * volume_j;
}

class Wcsph final : public Solver {
 public:
  Wcsph(const SiberneticConfig& config, const PhysicsConstants& constants, int threads);

  void Step() override;
  std::size_t steps_done() const override { return step_; }
  std::string name() const override { return "wcsph"; }
  int threads() const override { return threads_; }
  bool reference_equivalent() const override { return false; }
  std::span<const Float4> positions() const override { return out_position_; }
  std::span<const Float4> velocities() const override { return out_velocity_; }
  std::vector<float> Density() const override;
  std::span<const float> pressure() const override { return out_pressure_; }
  std::span<float> muscle_activation() override { return muscles_; }
  std::string parameters() const override;
  // The adaptive stepping since the last call, as one JSON object (see docs/wcsph.md).
  std::string TakeStepLog() override;
  void EnablePhaseTiming() override { clock_.Enable(); }
  std::vector<PhaseTime> phase_seconds() const override { return clock_.seconds(); }
  // Polled between sub-steps: when it returns true, Step() throws Cancelled (Run stops there, as
  // between steps). May be empty.
  void set_stop_requested(std::function<bool()> stop) { stop_requested_ = std::move(stop); }
  // A safe sub-step this many times shorter than the nominal step is a blow-up, not a run that
  // can finish (huge forces: hours for one step): Step() throws SimulationError.
  static constexpr double kMaxSubstepsPerStep = 1e5;

  // ---- For tests and measurements ----
  struct Stats {
    std::size_t substeps = 0, rollbacks = 0;
    double time_s = 0, last_dt_s = 0, dt_safe_s = 0;
    double max_density_variation = 0;  // max |ρ − ρ0|/ρ0 over the liquid, now
  };
  const Stats& stats() const { return stats_; }
  double spacing_m() const { return spacing_m_; }
  double sound_speed_m_s() const { return sound_speed_; }
  // The δ-SPH rate Σ_j DensityDiffusionPair · 2 δ h c_s of every liquid particle, external order.
  std::vector<float> DensityDiffusionRates() const;
  // The XSPH drift velocities of every liquid particle (external order, m/s).
  std::vector<Float4> XsphVelocities() const;
  // Overwrite the liquid's densities / velocities (external order) and re-evaluate the rates.
  void SetDensities(const std::vector<float>& density);
  void SetVelocities(const std::vector<Float4>& velocity);
  // Copies the state into the checkpoint / back from it (the optimistic step's rollback).
  void Checkpoint();
  void Restore();

 private:
  struct State {
    std::vector<float> x, y, z, vx, vy, vz, ax, ay, az, rho;
    std::vector<std::int32_t> row;  // internal index → configuration row
    std::vector<char> liquid;
    std::size_t since_reorder = 0;
    double time_s = 0;
  };

  // Per thread: the lists it wrote and the candidates of the cell it is listing.
  struct Candidates {
    std::vector<float> x, y, z;
    std::vector<std::int32_t> index;
    void Clear();
    void Add(const State& s, std::int32_t j);
  };
  struct ListScratch {
    std::vector<std::int32_t> lists, kept;
    std::vector<float> d2;
    Candidates all, liquid;  // every candidate; the liquid ones (for walls)
  };
  // The phases of a sub-step, for the per-phase profile.
  enum Phase { kKick, kDensity, kDrift, kReorder, kNeighbours, kForces, kControl, kPhaseCount };

  void Substep(double dt);
  void Kick(double half_dt);
  // Density rates and XSPH velocities at the current positions (one pass over the lists).
  void DensityRates();
  void DensityRate(std::size_t i);  // pairs.cpp, as Accelerate
  void DensityRateAvx512(std::size_t i);
  void AdvanceDensity(double dt);
  void Drift(double dt);
  void BuildNeighbours();
  void ListCell(int cell, ListScratch* scratch, int thread);
  void Evaluate();  // pressures and the liquid's accelerations
  // Pair sums of one particle (pairs.cpp), in 16 lanes by neighbour position k mod 16, the
  // lanes then added in order: the AVX-512 twins compute the same floats.
  void Accelerate(std::size_t i);
  void AccelerateAvx512(std::size_t i);
  void Reorder();
  double SafeDt() const;
  // SimulationError when `safe` is too short for the step to finish (kMaxSubstepsPerStep).
  void CheckProgress(double safe) const;
  double MaxDensityVariation() const;
  float Pressure(float rho) const;
  void WriteOutputs();
  void DeriveScales(const SiberneticConfig& config, const PhysicsConstants& constants);

  PhysicsConstants::Wcsph p_;
  int threads_;
  double scale_ = 1, nominal_dt_ = 0;
  double spacing_m_ = 0, h_ = 0, mass_ = 0, rho0_ = 1000, sound_speed_ = 0, tait_b_ = 0;
  float gravity_[3] = {0, 0, 0};
  float box_low_[3] = {0, 0, 0}, box_high_[3] = {0, 0, 0};
  WendlandC2<float> kernel_;
  State s_, checkpoint_;
  CellList cells_;
  std::vector<std::int32_t> process_;      // particles whose rates are computed (liquid first)
  std::size_t process_liquid_ = 0;         // how many of process_ are liquid
  std::vector<const std::int32_t*> list_;  // per particle: its neighbours
  std::vector<std::int32_t> list_count_;
  std::vector<ListScratch> scratch_;
  std::vector<std::size_t> list_begin_;   // per particle: offset in its thread's lists
  std::vector<std::int32_t> list_owner_;  // per particle: the thread that listed it
  std::vector<char> cell_has_liquid_, cell_active_;
  std::vector<std::int32_t> liquid32_;      // s_.liquid as 32-bit lanes (gathers)
  std::vector<std::int32_t> active_cells_;  // cells with liquid within one cell
  std::vector<float> drho_, xsph_x_, xsph_y_, xsph_z_, pressure_;
  std::vector<Float4> out_position_, out_velocity_, wall_velocity_;
  std::vector<float> out_pressure_, out_density_, muscles_;
  Stats stats_;
  std::size_t step_ = 0, cooldown_ = 0;
  std::function<bool()> stop_requested_;
  // Since the last TakeStepLog.
  std::size_t log_substeps_ = 0, log_rollbacks_ = 0;
  double log_dt_min_ = 0, log_dt_max_ = 0, log_variation_max_ = 0;
  PhaseClock<kPhaseCount> clock_{
      {"kick", "density_xsph", "drift", "reorder", "neighbours", "forces", "dt_control"}};
};

}  // namespace owval::engine::internal
