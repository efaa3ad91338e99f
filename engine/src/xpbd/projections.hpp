#pragma once
// XPBD constraint projections, free of any solver state so that each can be checked by hand
// [MMC16]. Positions in configuration units (cu); every particle has the same mass m, so inverse
// masses are in units of 1/m (1 for a moving particle, 0 for a fixed one) and a compliance α
// (per unit mass: s² for a bond whose stiffness is given per unit mass in s⁻²) enters as
// α̃ = α/dt².
//
//   [MMC16] M. Macklin, M. Müller, N. Chentanez. XPBD: position-based simulation of compliant
//           constrained dynamics. Motion in Games 2016, pp. 49-54 (eqs. 17-18).
//   [MM13]  M. Macklin, M. Müller. Position based fluids. ACM TOG 32(4), 104, 2013 (eqs. 1-14).
#include <algorithm>
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

// Position-based fluids' artificial pressure [MM13 §4, eqs. 13-14]: each pair's term of the
// density correction Δp_i = Σ_j (Δλ_i + Δλ_j + s_corr)·V0∇W(p_i − p_j) gets
// s_corr = −k·(W(|p_i − p_j|)/W(|Δq|))^n, a repulsion that grows as a pair closes in, so that a
// two-sided constraint (C < 0 pulls) cannot clump under-dense particles (the tensile
// instability). The paper's constants: k = 0.1, n = 4, |Δq| = 0.1-0.3 h. The paper adds the
// dimensionless s_corr to λ, which has units of length² (C is dimensionless, ∇C 1/length), so
// its k holds in one unit of length only; here lengths are measured in h (k·h² in cu²), which
// makes the push a fixed fraction of h whatever the configuration's units (docs/xpbd.md).
// strength = k·h² (cu²) ≥ 0, 0: off.
template <typename T>
struct TensileCorrection {
  T strength = 0;      // k·h², cu²
  T inverse_w_dq = 0;  // 1/W(|Δq|), with the density kernel's W
  int exponent = 4;    // n
  bool on() const { return strength > 0; }
  // s_corr (cu²) of a pair whose kernel value is w = W(|p_i − p_j|).
  T Of(T w) const {
    const T ratio = w * inverse_w_dq;
    T power = ratio;
    for (int e = 1; e < exponent; ++e) power *= ratio;
    return -strength * power;
  }
};

// A point kept on one side of a triangle's plane [MMC16; Müller et al. 2007, PBD §4, the
// triangle-point collision with the plane's normal held fixed over the projection]:
// C = side·n̂·(q − a) − thickness ≥ 0, n̂ = (b − a)×(c − a)/|·|, side = ±1 the side q keeps.
// Its gradients are side·n̂ for q and −β_k·side·n̂ for the corners, β the barycentric weights of
// q's projection onto the plane: Δλ = −C/(w_q + Σ_k w_k β_k²), q += w_q·Δλ·side·n̂, corner k
// −= w_k·β_k·Δλ·side·n̂. With equal masses and every w = 1 the moves sum to zero (momentum is
// conserved) and the corners take the liquid's push at Σ β_k·corner_k, the projection of q, on
// q's line of action: no torque, so angular momentum is conserved too. That holds only when the
// projection falls inside the triangle, as the triangle-point collision asks (the point passes
// through the triangle): outside it, weights clamped to the triangle put the reaction off that
// line, and on demo1's cube (every square split along the same diagonal) the couples added up
// to a steady spin (docs/xpbd.md). So a projection outside the triangle by more than
// kBarycentricSlack (rounding on a shared edge) is no contact; inside the slack the weights are
// clamped at 0 and renormalised. A contact (compliance 0) and an inequality: nothing moves while
// C ≥ 0. Returns Δλ (0 when nothing moved, the triangle is degenerate or q is not over it).
inline constexpr double kBarycentricSlack = 1e-4;

template <typename T>
T ProjectPointOffTriangle(Vec3<T>* q, Vec3<T>* a, Vec3<T>* b, Vec3<T>* c, T wq, T wa, T wb, T wc,
                          T side, T thickness) {
  const Vec3<T> ab{(*b)[0] - (*a)[0], (*b)[1] - (*a)[1], (*b)[2] - (*a)[2]};
  const Vec3<T> ac{(*c)[0] - (*a)[0], (*c)[1] - (*a)[1], (*c)[2] - (*a)[2]};
  const Vec3<T> aq{(*q)[0] - (*a)[0], (*q)[1] - (*a)[1], (*q)[2] - (*a)[2]};
  const Vec3<T> normal{ab[1] * ac[2] - ab[2] * ac[1], ab[2] * ac[0] - ab[0] * ac[2],
                       ab[0] * ac[1] - ab[1] * ac[0]};
  const T length = Norm(normal);
  if (!(length > 0)) return 0;
  const Vec3<T> n{side * normal[0] / length, side * normal[1] / length, side * normal[2] / length};
  const T constraint = n[0] * aq[0] + n[1] * aq[1] + n[2] * aq[2] - thickness;
  if (!(constraint < 0)) return 0;
  // Barycentric weights of q's projection: aq = β_b·ab + β_c·ac + (normal part).
  const T d00 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
  const T d01 = ab[0] * ac[0] + ab[1] * ac[1] + ab[2] * ac[2];
  const T d11 = ac[0] * ac[0] + ac[1] * ac[1] + ac[2] * ac[2];
  const T d20 = aq[0] * ab[0] + aq[1] * ab[1] + aq[2] * ab[2];
  const T d21 = aq[0] * ac[0] + aq[1] * ac[1] + aq[2] * ac[2];
  const T det = d00 * d11 - d01 * d01;  // |ab × ac|², > 0 here
  T beta[3] = {0, (d11 * d20 - d01 * d21) / det, (d00 * d21 - d01 * d20) / det};
  beta[0] = T(1) - beta[1] - beta[2];
  for (T weight : beta)
    if (!(weight >= -T(kBarycentricSlack))) return 0;  // not over the triangle (or NaN)
  T sum = 0;
  for (T& weight : beta) sum += weight = std::max(weight, T(0));
  for (T& weight : beta) weight /= sum;  // sum ≥ 1: the unclamped weights add to 1
  const T denominator =
      wq + wa * beta[0] * beta[0] + wb * beta[1] * beta[1] + wc * beta[2] * beta[2];
  if (!(denominator > 0)) return 0;
  const T dlambda = -constraint / denominator;
  Vec3<T>* corner[3] = {a, b, c};
  const T w[3] = {wa, wb, wc};
  for (int axis = 0; axis < 3; ++axis) {
    (*q)[axis] += wq * dlambda * n[axis];
    for (int k = 0; k < 3; ++k) (*corner[k])[axis] -= w[k] * beta[k] * dlambda * n[axis];
  }
  return dlambda;
}

}  // namespace owval::engine::internal
