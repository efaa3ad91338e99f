#pragma once
// XPBD constraint projections, free of any solver state so that each can be checked by hand
// [MMC16]. Positions in configuration units (cu); every particle has the same mass m, so inverse
// masses are in units of 1/m (1 for a moving particle, 0 for a fixed one) and a compliance α
// (per unit mass: s² for a bond whose stiffness is given per unit mass in s⁻²) enters as
// α̃ = α/dt².
//
//   [MMC16] M. Macklin, M. Müller, N. Chentanez. XPBD: position-based simulation of compliant
//           constrained dynamics. Motion in Games 2016, pp. 49-54 (eqs. 17-18).
//   [MM13]  M. Macklin, M. Müller. Position based fluids. ACM TOG 32(4), 104, 2013 (eqs. 1-12).
#include <array>
#include <cmath>

namespace owval::engine::internal {

template <typename T>
using Vec3 = std::array<T, 3>;

template <typename T>
T Norm(const Vec3<T>& a) {
  return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
}

// Distance constraint C = |p_a − p_b| − rest [MMC16 eqs. 17-18]:
// Δλ = (−C − α̃λ)/(w_a + w_b + α̃), p_a += w_a·Δλ·n, p_b −= w_b·Δλ·n with n = (p_a − p_b)/|·|.
// Accumulates λ and returns Δλ; does nothing (returns 0) for coincident points or w_a + w_b +
// α̃ = 0. α̃ → 0 gives the hard constraint: |p_a − p_b| = rest after one projection.
template <typename T>
T ProjectDistance(Vec3<T>* pa, Vec3<T>* pb, T wa, T wb, T rest, T alpha_tilde, T* lambda) {
  const Vec3<T> d{(*pa)[0] - (*pb)[0], (*pa)[1] - (*pb)[1], (*pa)[2] - (*pb)[2]};
  const T length = Norm(d);
  const T denominator = wa + wb + alpha_tilde;
  if (!(length > 0) || !(denominator > 0)) return 0;
  const T c = length - rest;
  const T dlambda = (-c - alpha_tilde * *lambda) / denominator;
  *lambda += dlambda;
  for (int a = 0; a < 3; ++a) {
    (*pa)[a] += wa * dlambda * d[a] / length;
    (*pb)[a] -= wb * dlambda * d[a] / length;
  }
  return dlambda;
}

// The density constraint C_i = ρ_i/ρ_rest − 1 = V0·(W(0) + Σ_j W(|p_i − p_j|)) − 1 with
// V0 = m/(ρ_rest·s³) the rest volume in cu³ [MM13 eq. 1], Wpoly6 for the density and ∇Wspiky
// for the gradient [MM13 §4]. Kernel coefficients in cu (poly6 = 315/(64π h⁹), spiky_gradient
// = −45/(π h⁶)). Returns C and fills the gradient with respect to p_i; ∇_{p_j} C_i is then
// −V0·∇W(p_i − p_j).
template <typename T>
struct DensityKernel {
  T h, h2, rest_volume, poly6, spiky_gradient;

  T W(T r2) const {
    const T q = h2 - r2;
    return r2 < h2 ? poly6 * q * q * q : T(0);
  }
  // V0·∇Wspiky(d) for the offset d = p_i − p_j.
  Vec3<T> Gradient(const Vec3<T>& d) const {
    const T r = Norm(d);
    if (!(r > 0 && r < h)) return {0, 0, 0};
    const T f = rest_volume * spiky_gradient * (h - r) * (h - r) / r;
    return {f * d[0], f * d[1], f * d[2]};
  }
};

}  // namespace owval::engine::internal
