#pragma once
// Extended position-based dynamics over Sibernetic's configurations [MMC16], with position-based
// fluids' density constraint [MM13], as the native ports build it (see docs/xpbd.md). Per step:
//   neighbours (shared grid, x(t)) → SPH density and the interleaved forces (gravity always;
//   Sibernetic's viscosity, cohesion and SPH pressure-gradient force, each switchable), held
//   over the step
//   → n substeps of h = dt/n [M19], each:
//       predict p = x + h·v*/s with v* = v + h·a
//       → K × {density constraints (both directions; xpbd_tensile_correction adds [MM13]'s
//              artificial pressure s_corr, eqs. 13-14; xpbd_body_push_only keeps an elastic
//              particle's multiplier from pulling its liquid neighbours), bonds (one-sided
//              distance constraints, as Sibernetic's springs act only on their own row's
//              particle), walls [IAGT10], box}
//       → v = (p − x)·s/h, wall contacts' velocity (restitution, friction), floor restitution
//   → the shared membrane pass (xpbd_membranes = 0, the default), or, with xpbd_membranes = 1,
//     a membrane constraint in every projection pass instead: each liquid particle near a
//     membrane triangle (Sibernetic's selection, found once per step at x(t)) is kept on the side
//     of the triangle's plane it was on at x(t), the correction shared with the triangle's
//     corners (projections.hpp, ProjectPointOffTriangle); one that crossed where no triangle
//     lies under it is kept off the nearest edge or vertex [BFA02] (ProjectPointOffEdge,
//     ProjectPointOffVertex).
// Split (xpbd_density_passes = m > 0, the default): the n substeps hold only the bonds (predict,
// bonds, v = (p − x)·s/h); after every n/m of them one correction of H = dt/m projects the
// density constraints and walls, v += Δp·s/H, wall contacts' velocity. m = 0: the scheme above.
// Like Sibernetic's first step, step 0 moves nothing but the membrane pass.
// The scalar of the projections is a template parameter: float for runs, double for gradient
// checks; neighbour search, walls and membranes work on a float copy of the positions.
//
//   [MMC16] M. Macklin, M. Müller, N. Chentanez. XPBD: position-based simulation of compliant
//           constrained dynamics. Motion in Games 2016.
//   [MM13]  M. Macklin, M. Müller. Position based fluids. ACM TOG 32(4), 2013.
//   [IAGT10] M. Ihmsen et al. Boundary handling and adaptive time-stepping for PCISPH. 2010.
//   [M19]   M. Macklin, K. Storey, M. Lu, P. Terdiman, N. Chentanez, S. Jeschke, M. Müller.
//           Small steps in physics simulation. SCA 2019.
//   [BFA02] R. Bridson, R. Fedkiw, J. Anderson. Robust treatment of collisions, contact and
//           friction for cloth animation. SIGGRAPH 2002 (point-edge and point-vertex contacts).
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "kernels/sph_constants.hpp"
#include "neighbours/neighbour_grid.hpp"
#include "owval/engine/solver.hpp"
#include "phase_clock.hpp"
#include "phases/density.hpp"
#include "state/elastic_matter.hpp"
#include "state/particle_state.hpp"
#include "xpbd/bond_pushes.hpp"
#include "xpbd/projections.hpp"

namespace owval::engine::internal {

// The substeps per step: the set xpbd_substeps, or (0) derived from the stiffest bond. A
// one-iteration XPBD substep of h is implicit Euler on a bond (ω² = k_eff): its oscillation
// keeps (1 + ω²h²)^(−1/2) of its amplitude per substep, ≈ exp(−πωh) per period. n is the least
// count whose loss per period, πω·dt/n, is within xpbd_damping_budget, and at least 4 (the
// projection passes per step the K study found stable for the liquid, docs/xpbd.md).
int SubstepsOf(const SiberneticConfig& config, const PhysicsConstants& constants);

// The density constraint's compliance α (s²/cu²; α̃ = α/h²): the set xpbd_density_compliance,
// or (0) derived as a weakly compressible liquid's [Monaghan 1994, Mach 0.1]: α = (s/c)² with
// c = 10·√(2 g H), H the height of the highest liquid particle (any moving one when there is no
// liquid) above the box floor, so the constraint's energy C²/(2α) is the liquid's elastic
// energy at bulk modulus ρ0 c². A hard constraint (α = 0) turns each substep's Jacobi
// correction into a velocity Δp/h and is unstable with substeps; with no gravity there is no
// velocity scale and the derived α is 0.
double DensityComplianceOf(const SiberneticConfig& config, const PhysicsConstants& constants);

// What the density constraint's estimator reads where Sibernetic's reads ρ0 (kg/m³): ρ0 +
// m·W(0)/s³. Sibernetic's density sums m·Wpoly6 over the particle's 32-slot list *without* a
// self term (floored at the self term, sphFluid.cl:473-510 and 869-925), and PCISPH raises
// pressure until that sum reads ρ0; the constraint sums the same list *with* the self term, so
// the packing PCISPH drives the liquid to reads ρ0 + m·W(0)/s³ in it (demo1: 1000 + 207.53;
// the initial lattice reads 862.5 in Sibernetic's sum, 1070.1 in the constraint's). Not the
// default (docs/xpbd.md, "The rest density PCISPH targets"): `--set xpbd_rest_density=` this
// value, printed in the run's scheme_parameters as sibernetic_target_density.
double SiberneticTargetDensityOf(const PhysicsConstants& constants);

template <typename T>
class Xpbd final : public Solver {
 public:
  Xpbd(const SiberneticConfig& config, const PhysicsConstants& constants, int threads);

  void Step() override;
  std::size_t steps_done() const override { return step_; }
  std::string name() const override { return "xpbd"; }
  int threads() const override { return threads_; }
  bool reference_equivalent() const override { return false; }
  std::span<const Float4> positions() const override { return state_.position; }
  std::span<const Float4> velocities() const override { return state_.velocity; }
  std::vector<float> Density() const override;
  std::span<const float> pressure() const override { return state_.pressure; }
  std::span<float> muscle_activation() override { return matter_.muscle_activation; }
  std::string parameters() const override;
  // The particle state: positions, neighbour lists of the last step (tests read them).
  const ParticleState& state() const { return state_; }
  NonFinite FirstNonFinite() const override;
  void EnablePhaseTiming() override { clock_.Enable(); }
  std::vector<PhaseTime> phase_seconds() const override { return clock_.seconds(); }
  // Checkpoints: the float state the phases share, the solver's positions and velocities in T
  // and the muscle activations; everything else is rebuilt within a step.
  void SaveState(std::string* out) const override;
  void RestoreState(const std::string& state, const std::string& source) override;
  bool can_checkpoint() const override { return true; }

  // The rest density the density constraints use (kg/m³), derived or set.
  double rest_density() const { return rest_density_; }
  // SiberneticTargetDensityOf(constants): the rest density at which the constraint holds the
  // packing PCISPH drives the liquid to (kg/m³).
  double sibernetic_target_density() const { return sibernetic_target_density_; }
  // The density constraint's compliance (s²/cu²), derived or set.
  double density_compliance() const { return density_compliance_; }
  // Positions in the solver's scalar (cu), for tests.
  const std::vector<Vec3<T>>& exact_positions() const { return x_; }

 private:
  struct Bond {
    std::int32_t particle, partner;
    T rest_cu, stiffness;  // k_eff in s⁻² (Sibernetic's k, or k·factor off the worm body)
    int muscle;            // 1..96, or 0
  };

  // The phases of a step, for the per-phase profile: "substeps" is the unsplit scheme's
  // (density_passes = 0), "bond_substeps" and "corrections" the split scheme's.
  enum Phase {
    kNeighbours,
    kDensity,
    kForces,
    kSubsteps,
    kBondSubsteps,
    kCorrections,
    kMembranes,
    kPhaseCount
  };

  void ComputeForces();
  void HoldAcceleration();
  void Substep(T h);
  void BondSubstep(T h);
  void ShareBondSubsteps();
  void SharedBondSubsteps(T h, int substeps);
  bool BondSubstepInLanes(T h, T to_cu, T scale, bool predict);
  bool BondSubstepsInLanes(T h, int substeps);
  void Correct(T h);
  void Predict(T h);
  void ProjectDensity(T h);
  void ProjectDensityInLanes(T alpha_tilde);
  void UpdateDensityLambda(std::int32_t i, T w, T norm2, T alpha_tilde);
  T PairMultiplier(std::int32_t i, std::int32_t j) const;
  T StiffnessOf(const Bond& bond) const;
  void ProjectBonds(T h);
  void BondComplianceOf(T h);
  // `first_pass`: the substep's first pass (λ starts at 0); `start_written`: bond_start_ already
  // holds p; `last_pass`: p is left as predicted (the update reads only the corrections).
  void ProjectBondsOneSided(bool first_pass, bool start_written, bool last_pass);
  void ProjectBoundaries();
  void UpdateVelocities(T h);
  void WriteFloatState(std::int32_t i);
  void WallVelocity(std::int32_t i, const Vec3<T>& predicted, T restitution);
  void InteractWithMembranes();
  void FindMembraneContacts();
  struct MembraneFeature;
  void FindMembraneFeatures(std::int32_t liquid, std::uint32_t triangles_begin);
  void MeasureCornerDistances(const Float4& x, std::uint32_t begin, std::uint32_t end);
  bool AddFeatureOwners(const Float4& x, int corner, int other_corner);
  bool FeatureCrossed(const MembraneFeature& feature) const;
  void ProjectMembranes();
  double DerivedRestDensity() const;
  // The step's neighbour lists (grid_.Refresh), reciprocal ones under xpbd_reciprocal_lists.
  void RefreshLists();

  SphConstants k_, k_forces_;
  PhysicsConstants::Xpbd parameters_;
  float delta_;
  // The projections' loops fork only over this many moving particles. In the unsplit scheme
  // they run on every substep: demo1's 343 took 25x longer on two threads than on one (each
  // substep's fork/join, on a shared machine). In the split scheme they run once per step (the
  // density and wall correction): demo1's correction took 0.36-0.42 s of a 5,000-step run
  // serial and 0.23-0.25 s forked over two threads.
  static constexpr std::size_t kParallelMoversPerSubstep = 4096, kParallelMoversPerStep = 256;
  int threads_, substeps_;
  bool parallel_ = false;
  Box box_;
  ParticleState state_;
  NeighbourGrid grid_;
  ElasticMatter matter_;
  std::vector<Bond> bonds_;
  std::vector<std::size_t> bond_rows_;  // bonds_[bond_rows_[r], bond_rows_[r + 1]): one row
  // The float solver's bond pass in vector lanes (bond_pushes.hpp), when the CPU has them: it
  // then holds the bonds' λ and α̃ in its own layout, and the density projection takes its
  // lanes too (density_lanes.hpp).
  std::optional<BondLanes> bond_lanes_;
  bool moving_block_ = false;  // the moving particles are rows [first, first + count)
  double rest_density_ = 0, sibernetic_target_density_ = 0, density_compliance_ = 0;
  DensityKernel<T> kernel_{};
  // [MM13]'s s_corr (xpbd_tensile_correction; off by default) and, per particle, its part of a
  // density pass's Δp, Σ_j s_corr·V0∇W (it does not depend on the pass's Δλ).
  TensileCorrection<T> tensile_{};
  std::vector<Vec3<T>> tensile_dp_;
  std::vector<std::int32_t> moving_;  // per particle: −1 moving, 0 fixed (a lane mask)
  std::vector<Vec3<T>> x_, v_, p_, dp_;
  std::vector<Vec3<T>> held_acceleration_;  // per moving particle (HoldAcceleration)
  std::vector<Vec3<T>> bond_start_;         // the split's bond pass: positions as the pass began
  // The split's bond substeps: each bonded particle's sum of pushes in the substep, unrounded by
  // its position's ulp (zero for the others), and what each substep's rounding of the position
  // dropped (bond_pushes.hpp: why).
  std::vector<Vec3<T>> bond_correction_, position_remainder_;
  // The split scheme's bond substeps on several threads at once (SharedBondSubsteps): per
  // thread, one part of BondLanes' groups and the moving particles it predicts and updates,
  // from its first row's particle to the next part's (bondless ones included). Empty: the
  // substeps run serial.
  struct BondShare {
    std::size_t first_group = 0, last_group = 0;
    std::int32_t first_particle = 0, end_particle = 0;  // moving particles [first, end)
  };
  std::vector<BondShare> bond_shares_;
  std::vector<Vec3<T>> bond_start_next_;  // SharedBondSubsteps: every other substep's start
  std::vector<Vec3<T>> slot_gradient_;    // ProjectDensity: V0∇W per moving particle and slot
  std::vector<float> lane_record_;        // the same in lanes, with the lists (density_lanes.hpp)
  std::vector<int> lane_slots_;           // per lane group: the slots its record holds
  std::vector<Vec3<T>> wall_normal_;      // a substep's last wall push direction, or zero
  double wall_friction_ = 1;              // Sibernetic's 0.99 per step, per substep
  std::vector<T> density_lambda_, density_dlambda_, bond_lambda_, bond_alpha_tilde_;
  // What bond_alpha_tilde_ was computed for (BondComplianceOf): the substep h, or −1 before the
  // first step, and the muscle activations.
  T compliance_h_ = T(-1);
  std::vector<float> compliance_activation_;
  std::vector<Float4> pressure_acceleration_, membrane_scratch_;
  std::vector<Float4> membrane_before_;  // per moving particle, as the membrane pass began
  // xpbd_membranes = 1: a liquid particle and a triangle it must stay off, with the side of the
  // triangle's plane (±1, along (b − a)×(c − a)) it was on at the step's start.
  struct MembraneContact {
    std::int32_t liquid;
    std::array<int, 3> corners;
    T side;
  };
  std::vector<MembraneContact> membrane_contacts_;
  // xpbd_membranes = 1: an edge (corners[1] ≥ 0) or a vertex (corners[1] = −1) of the liquid
  // particle's triangles, within r0 of it at the step's start, that it must not leave through
  // where no triangle lies under it. `owners` (a range of membrane_feature_owners_) are the
  // membrane's triangles meeting there, each with the side of its plane the particle was on;
  // `triangles` (a range of membrane_contacts_) are the particle's own triangle contacts.
  struct MembraneFeature {
    std::int32_t liquid;
    std::array<int, 2> corners;
    std::uint32_t owners_begin, owners_end, triangles_begin, triangles_end;
  };
  std::vector<MembraneFeature> membrane_features_;
  std::vector<MembraneContact> membrane_feature_owners_;
  std::vector<std::uint64_t> feature_scratch_;  // FindMembraneFeatures' edges seen
  // MeasureCornerDistances: per particle, the visit that last measured it and its distance².
  std::vector<std::uint64_t> corner_visit_;
  std::vector<double> corner_distance2_;
  std::uint64_t corner_visit_stamp_ = 0;
  mutable internal::OutputDensity output_density_;  // for Density()
  std::size_t step_ = 0;
  PhaseClock<kPhaseCount> clock_{
      {"neighbours", "density", "forces", "substeps", "bond_substeps", "corrections", "membranes"}};
};

extern template class Xpbd<float>;
extern template class Xpbd<double>;

}  // namespace owval::engine::internal
