#pragma once
// The Wendland C2 kernel in three dimensions, the WCSPH scheme's kernel (engine/src/wcsph/).
// With q = r/h and support radius 2h:
//   W(r)   = 21/(16π h³) · (1 − q/2)⁴ (2q + 1)            for 0 ≤ q < 2, else 0
//   dW/dr  = 21/(16π h⁴) · (−5q) (1 − q/2)³
//   ∇_i W(x_i − x_j) = dW/dr · (x_i − x_j)/r               (zero at r = 0)
// Unlike the cubic spline it has no pairing instability, and its gradient vanishes at r = 0.
//
//   [W95]  H. Wendland. Piecewise polynomial, positive definite and compactly supported radial
//          functions of minimal degree. Adv. Comput. Math. 4 (1995) 389-396 (ψ_{3,1}).
//   [DA12] W. Dehnen, H. Aly. Improving convergence in smoothed particle hydrodynamics
//          simulations without pairing instability. MNRAS 425 (2012) 1068-1082 (Table 1: the
//          3-D normalisation 21/(2π) for support radius H = 2h, i.e. 21/(16π h³)).
#include "kernels/kernels.hpp"

namespace owval::engine::internal {

// 21/(16π h³): W(0) and the normalisation of the kernel with support 2h.
inline double WendlandC2Coefficient(double h) { return 21.0 / (16.0 * kPi * h * h * h); }

// The kernel's pieces for one h, formed once: per pair only a few multiplications remain.
template <typename T>
struct WendlandC2 {
  T h = 1, support = 2, support2 = 4, inverse_h = 1;
  T w_coefficient = 0;         // 21/(16π h³)
  T gradient_coefficient = 0;  // 21/(16π h⁴) · (−5), times q (1 − q/2)³

  static WendlandC2 ForRadius(double h) {
    WendlandC2 k;
    k.h = T(h);
    k.support = T(2 * h);
    k.support2 = T(4 * h * h);
    k.inverse_h = T(1 / h);
    k.w_coefficient = T(WendlandC2Coefficient(h));
    k.gradient_coefficient = T(-5 * WendlandC2Coefficient(h) / h);
    return k;
  }

  // W at distance r (any r ≥ 0).
  T W(T r) const {
    const T q = r * inverse_h;
    if (!(q < T(2))) return T(0);
    const T u = T(1) - T(0.5) * q;
    const T u2 = u * u;
    return w_coefficient * u2 * u2 * (T(2) * q + T(1));
  }
  // dW/dr divided by r: ∇_i W = GradientOverR(r) · (x_i − x_j). Finite at r = 0 (the limit).
  T GradientOverR(T r) const {
    const T q = r * inverse_h;
    if (!(q < T(2))) return T(0);
    const T u = T(1) - T(0.5) * q;
    return gradient_coefficient * inverse_h * u * u * u;  // (−5q u³ · c/h) / r = −5 u³ c/h²
  }
};

}  // namespace owval::engine::internal
