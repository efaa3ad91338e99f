#pragma once
// The SPH smoothing kernels, as named functions every phase and scheme calls. Each kernel is
// split the way Sibernetic evaluates it: a coefficient that depends on h only (formed once, in
// double, by SphConstants::From and multiplied by the mass there) and a shape in r that the
// phases evaluate per pair in float, in the operation order of sphFluid.cl. The full kernels W
// (coefficient · shape, for any scalar) are what the tests integrate and differentiate.
//
//   [MCG03] M. Müller, D. Charypar, M. Gross. Particle-based fluid simulation for interactive
//           applications. SCA 2003, pp. 154-159. (Wpoly6 eq. 20, Wspiky eq. 21, Wviscosity
//           eq. 22 and its Laplacian.)
//   [IAGT10] M. Ihmsen, N. Akinci, M. Gissler, M. Teschner. Boundary handling and adaptive
//           time-stepping for PCISPH. VRIPHYS 2010 (the wall weight, eq. 10).
#include <algorithm>
#include <cmath>

#include "kernels/fma.hpp"

namespace owval::engine::internal {

inline constexpr double kPi = 3.14159265358979323846;  // M_PI, a double, as Sibernetic's host

// ---- Coefficients (double, as Sibernetic's host forms them: owConfigProperty.cpp:226-244) ----

// Wpoly6(r) = 315/(64π h⁹) · (h² − r²)³.
inline double Wpoly6Coefficient(double h) { return 315.0 / (64.0 * kPi * std::pow(h, 9.0)); }
// ∇Wspiky(r) = −45/(π h⁶) · (h − r)² · r̂.
inline double SpikyGradientCoefficient(double h) { return -45.0 / (kPi * std::pow(h, 6.0)); }
// Wspiky(r) = 15/(π h⁶) · (h − r)³.
inline double SpikyCoefficient(double h) { return 15.0 / (kPi * std::pow(h, 6.0)); }
// ∇²Wviscosity(r) = 45/(π h⁶) · (h − r) (Sibernetic uses −∇Wspiky's coefficient).
inline double ViscosityLaplacianCoefficient(double h) { return -SpikyGradientCoefficient(h); }
// Wviscosity(r) = 15/(2π h³) · (−r³/(2h³) + r²/h² + h/(2r) − 1).
inline double ViscosityCoefficient(double h) { return 15.0 / (2.0 * kPi * std::pow(h, 3.0)); }

// ---- Shapes (the per-pair part, 0 outside the support where the caller does not test) ----

// (h² − r²)³ as (q·q)·q, for r² < h².
template <typename T>
inline T Wpoly6Shape(T h2, T r2) {
  const T q = h2 - r2;
  return q * q * q;
}

// Adds (h² − r²)³ to sum when r² < h², the last product fused with the addition as PoCL
// contracts sphFluid.cl:499 and :906. The density sums accumulate with this.
inline float AccumulateWpoly6(float h2, float r2, float sum) {
  if (!(r2 < h2)) return sum;
  const float q = h2 - r2;
  return Fma(q * q, q, sum);
}

// (h − r)², the magnitude part of ∇Wspiky, for r < h.
template <typename T>
inline T SpikyGradientShape(T h, T r) {
  return (h - r) * (h - r);
}

// (h − r), the viscosity kernel's Laplacian without its coefficient, for r < h.
template <typename T>
inline T ViscosityLaplacianShape(T h, T r) {
  return h - r;
}

// The wall and membrane weight max(0, (r0 − d)/r0) [IAGT10 eq. 10].
inline float BoundaryWeight(float r0, float d) { return std::max(0.0f, (r0 - d) / r0); }

// ---- Full kernels (for tests and for schemes that need W itself; r and h in one unit) ----

template <typename T>
inline T Wpoly6(T h, T r) {
  return r < h ? T(Wpoly6Coefficient(double(h))) * Wpoly6Shape(h * h, r * r) : T(0);
}

// ∇Wpoly6 at offset (x, y, z) = −6·315/(64π h⁹) · (h² − r²)² · (x, y, z).
template <typename T>
inline void Wpoly6Gradient(T h, const T offset[3], T gradient[3]) {
  const T r2 = offset[0] * offset[0] + offset[1] * offset[1] + offset[2] * offset[2];
  const T q = h * h - r2;
  const T factor = r2 < h * h ? T(-6.0 * Wpoly6Coefficient(double(h))) * q * q : T(0);
  for (int a = 0; a < 3; ++a) gradient[a] = factor * offset[a];
}

template <typename T>
inline T Wspiky(T h, T r) {
  return r < h ? T(SpikyCoefficient(double(h))) * (h - r) * (h - r) * (h - r) : T(0);
}

// ∇Wspiky at offset (x, y, z); zero at r = 0 and outside the support.
template <typename T>
inline void SpikyGradient(T h, const T offset[3], T gradient[3]) {
  const T r = std::sqrt(offset[0] * offset[0] + offset[1] * offset[1] + offset[2] * offset[2]);
  const T factor =
      r > 0 && r < h ? T(SpikyGradientCoefficient(double(h))) * SpikyGradientShape(h, r) / r : T(0);
  for (int a = 0; a < 3; ++a) gradient[a] = factor * offset[a];
}

template <typename T>
inline T Wviscosity(T h, T r) {
  if (!(r > 0 && r < h)) return T(0);
  const T x = r / h;
  return T(ViscosityCoefficient(double(h))) * (-x * x * x / 2 + x * x + 1 / (2 * x) - 1);
}

template <typename T>
inline T ViscosityLaplacian(T h, T r) {
  return r < h ? T(ViscosityLaplacianCoefficient(double(h))) * ViscosityLaplacianShape(h, r) : T(0);
}

}  // namespace owval::engine::internal
