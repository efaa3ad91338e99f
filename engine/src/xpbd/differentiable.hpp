#pragma once
// The differentiable XPBD model behind owval/engine/gradient.hpp: one step forward recording its
// tape, one step backward from that tape, and the neighbour search they share.
#include <cstddef>
#include <vector>

#include "owval/engine/config.hpp"
#include "owval/engine/gradient.hpp"
#include "xpbd/adjoint.hpp"

namespace owval::engine::internal::adjoint {

// What one projection pass's backward needs: the moving particles' positions and multipliers
// before its kernels (indexed as Setup::movers; fixed particles never move), its Δλ and
// denominators, and each bond's ends before its projection.
struct PassTape {
  std::vector<Vec3<double>> p_before_density, p_before_box;
  std::vector<double> lambda_density, dlambda, denominator;
  std::vector<double> lambda_bonds;                         // per bond
  std::vector<Vec3<double>> bond_partners, bond_particles;  // per bond
};
struct SubstepTape {
  std::vector<Vec3<double>> x, p_final;  // moving particles: the substep's input, final p
  std::vector<Vec3<double>> v;           // a split step's correction: its input velocity
  std::vector<PassTape> passes;
  bool correction = false;  // a split step's correction (else a substep or a bond substep)
};
// Everything one step's backward needs: its input state (every particle), neighbour lists, the
// SPH density and forces (once per step), and each substep's tape.
struct StepTape {
  Neighbours nb;
  Field<double> x, v, a;
  std::vector<double> rho;
  std::vector<SubstepTape> substeps;
  std::size_t Bytes() const;
};

// Lists of every moving particle's neighbours within h (cu) at x, in a fixed order (cells in
// z, y, x order, particles in index order within a cell).
Neighbours FindNeighbours(const Setup<double>& S, const Field<double>& x);

Setup<double> SetupOf(const SiberneticConfig& config, const PhysicsConstants& constants);
Parameters<double> DefaultParametersOf(const SiberneticConfig& config,
                                       const PhysicsConstants& constants);

// One step x, v → x', v'; fills the tape when given.
void StepForward(const Setup<double>& S, const Parameters<double>& theta, const Field<double>& x,
                 const Field<double>& v, Field<double>* x_next, Field<double>* v_next,
                 StepTape* tape);
// x_bar, v_bar: the cotangents of x', v' in, of x, v out; theta_bar accumulates.
void StepBackward(const Setup<double>& S, const Parameters<double>& theta, const StepTape& tape,
                  Field<double>* x_bar, Field<double>* v_bar, Parameters<double>* theta_bar);

// The interval the density constraint's compliance is scaled by: the split step's correction
// (the step/m), else the substep.
inline double DensityDt(const Setup<double>& S) {
  return S.density_passes > 0 ? S.correction_dt : S.dt;
}

// The rest volume V0 = m/(ρ_rest s³) (cu³) and α̃ = α/dt² of the density constraint.
inline double RestVolume(const Setup<double>& S, const Parameters<double>& t) {
  return S.mass / (t[kRestDensity] * S.s * S.s * S.s);
}
inline double DensityAlphaTilde(const Setup<double>& S, const Parameters<double>& t) {
  return t[kAlphaDensity] / (DensityDt(S) * DensityDt(S));
}

}  // namespace owval::engine::internal::adjoint
