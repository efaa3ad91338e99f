// The WCSPH scheme's pair sums (most of a sub-step's time): a particle's acceleration, and its
// density rate with its XSPH velocity, each over its neighbour list. The sums run in 16 lanes
// (neighbour k in lane k mod 16) and the lanes are added in order at the end, so that the
// AVX-512 twins (16 neighbours per instruction, gathered) compute the same floats as the scalar
// code, operation for operation (the engine compiles with -ffp-contract=off; see
// kernels/simd.hpp for the convention and the switch that tests use).
#include <immintrin.h>

#include <cmath>
#include <vector>

#include "kernels/simd.hpp"
#include "wcsph/wcsph.hpp"

namespace owval::engine::internal {
namespace {

constexpr int kLanes = 16;

float SumLanes(const float* lane) {
  float sum = 0;
  for (int l = 0; l < kLanes; ++l) sum += lane[l];
  return sum;
}

__attribute__((target("avx512f"), always_inline)) inline float SumLanes(__m512 v) {
  float lane[kLanes];
  _mm512_storeu_ps(lane, v);
  return SumLanes(lane);
}

// The floats of v at the lanes' indices j (0 in the lanes off).
__attribute__((target("avx512f"), always_inline)) inline __m512 Gather(
    __mmask16 lanes, __m512i j, const std::vector<float>& v) {
  return _mm512_mask_i32gather_ps(_mm512_setzero_ps(), lanes, j, v.data(), 4);
}

__attribute__((target("avx512f"))) __mmask16 Lanes(int left) {
  return left >= kLanes ? __mmask16(0xFFFF) : __mmask16((1u << left) - 1);
}

}  // namespace

// Pressure force, artificial viscosity [Mon92] and gravity on liquid particle i.
void Wcsph::Accelerate(std::size_t i) {
  if (UseAvx512()) return AccelerateAvx512(i);
  const float m = float(mass_), h = float(h_), c = float(sound_speed_);
  const float alpha = float(p_.viscosity_alpha), viscosity = -alpha * c, soft = 0.01f * h * h;
  const float xi = s_.x[i], yi = s_.y[i], zi = s_.z[i];
  const float vxi = s_.vx[i], vyi = s_.vy[i], vzi = s_.vz[i];
  const float rhoi = s_.rho[i], pri = pressure_[i] / (rhoi * rhoi);
  float ax[kLanes] = {}, ay[kLanes] = {}, az[kLanes] = {};
  const std::int32_t* list = list_[i];
  for (std::int32_t k = 0; k < list_count_[i]; ++k) {
    const std::size_t j = std::size_t(list[k]);
    const int l = k % kLanes;
    const float dx = xi - s_.x[j], dy = yi - s_.y[j], dz = zi - s_.z[j];
    const float r2 = dx * dx + dy * dy + dz * dz;
    const float f = kernel_.GradientOverR(std::sqrt(r2));  // ∇_i W_ij = f · r_ij
    const float vr = (vxi - s_.vx[j]) * dx + (vyi - s_.vy[j]) * dy + (vzi - s_.vz[j]) * dz;
    const float rhoj = s_.rho[j];
    float coefficient = pri + pressure_[j] / (rhoj * rhoj);
    if (alpha > 0 && vr < 0)
      coefficient += viscosity * (h * vr / (r2 + soft)) / (0.5f * (rhoi + rhoj));
    const float push = -m * coefficient * f;
    ax[l] += push * dx;
    ay[l] += push * dy;
    az[l] += push * dz;
  }
  s_.ax[i] = SumLanes(ax) + gravity_[0];
  s_.ay[i] = SumLanes(ay) + gravity_[1];
  s_.az[i] = SumLanes(az) + gravity_[2];
}

__attribute__((target("avx512f"))) void Wcsph::AccelerateAvx512(std::size_t i) {
  const float h = float(h_), alpha = float(p_.viscosity_alpha);
  const __m512 minus_m = _mm512_set1_ps(-float(mass_)), hv = _mm512_set1_ps(h);
  const __m512 viscosity = _mm512_set1_ps(-alpha * float(sound_speed_));
  const __m512 soft = _mm512_set1_ps(0.01f * h * h), half = _mm512_set1_ps(0.5f);
  const __m512 one = _mm512_set1_ps(1.0f), two = _mm512_set1_ps(2.0f), zero = _mm512_setzero_ps();
  const __m512 inverse_h = _mm512_set1_ps(kernel_.inverse_h);
  const __m512 gradient = _mm512_set1_ps(kernel_.gradient_coefficient * kernel_.inverse_h);
  const __m512 xi = _mm512_set1_ps(s_.x[i]), yi = _mm512_set1_ps(s_.y[i]),
               zi = _mm512_set1_ps(s_.z[i]);
  const __m512 vxi = _mm512_set1_ps(s_.vx[i]), vyi = _mm512_set1_ps(s_.vy[i]),
               vzi = _mm512_set1_ps(s_.vz[i]);
  const float rho_i = s_.rho[i];
  const __m512 rhoi = _mm512_set1_ps(rho_i), pri = _mm512_set1_ps(pressure_[i] / (rho_i * rho_i));
  __m512 ax = zero, ay = zero, az = zero;
  const std::int32_t* list = list_[i];
  const int count = list_count_[i];
  for (int k = 0; k < count; k += kLanes) {
    const __mmask16 lanes = Lanes(count - k);
    const __m512i j = _mm512_maskz_loadu_epi32(lanes, list + k);
    const __m512 dx = _mm512_sub_ps(xi, Gather(lanes, j, s_.x)),
                 dy = _mm512_sub_ps(yi, Gather(lanes, j, s_.y)),
                 dz = _mm512_sub_ps(zi, Gather(lanes, j, s_.z));
    const __m512 r2 = _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(dx, dx), _mm512_mul_ps(dy, dy)),
                                    _mm512_mul_ps(dz, dz));
    const __m512 q = _mm512_mul_ps(_mm512_maskz_sqrt_ps(lanes, r2), inverse_h);
    const __m512 u = _mm512_sub_ps(one, _mm512_mul_ps(half, q));
    const __mmask16 inside = _mm512_mask_cmp_ps_mask(lanes, q, two, _CMP_LT_OQ);
    const __m512 f = _mm512_maskz_mul_ps(inside, _mm512_mul_ps(_mm512_mul_ps(gradient, u), u), u);
    const __m512 vr =
        _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(_mm512_sub_ps(vxi, Gather(lanes, j, s_.vx)), dx),
                                    _mm512_mul_ps(_mm512_sub_ps(vyi, Gather(lanes, j, s_.vy)), dy)),
                      _mm512_mul_ps(_mm512_sub_ps(vzi, Gather(lanes, j, s_.vz)), dz));
    const __m512 rhoj = Gather(lanes, j, s_.rho);
    __m512 coefficient =
        _mm512_add_ps(pri, _mm512_div_ps(Gather(lanes, j, pressure_), _mm512_mul_ps(rhoj, rhoj)));
    if (alpha > 0) {
      const __mmask16 approaching = _mm512_mask_cmp_ps_mask(lanes, vr, zero, _CMP_LT_OQ);
      const __m512 mu = _mm512_div_ps(_mm512_mul_ps(hv, vr), _mm512_add_ps(r2, soft));
      const __m512 term = _mm512_div_ps(_mm512_mul_ps(viscosity, mu),
                                        _mm512_mul_ps(half, _mm512_add_ps(rhoi, rhoj)));
      coefficient = _mm512_mask_add_ps(coefficient, approaching, coefficient, term);
    }
    const __m512 push = _mm512_mul_ps(_mm512_mul_ps(minus_m, coefficient), f);
    ax = _mm512_mask_add_ps(ax, lanes, ax, _mm512_mul_ps(push, dx));
    ay = _mm512_mask_add_ps(ay, lanes, ay, _mm512_mul_ps(push, dy));
    az = _mm512_mask_add_ps(az, lanes, az, _mm512_mul_ps(push, dz));
  }
  s_.ax[i] = SumLanes(ax) + gravity_[0];
  s_.ay[i] = SumLanes(ay) + gravity_[1];
  s_.az[i] = SumLanes(az) + gravity_[2];
}

// Continuity [Mon92] plus δ-SPH [MC09] from the densities the sub-step starts with; for a liquid
// particle also XSPH [Mon89 eq. 2.6]: u_i = v_i + ε Σ_j m/ρ̄_ij (v_j − v_i) W_ij over the liquid.
void Wcsph::DensityRate(std::size_t i) {
  if (UseAvx512()) return DensityRateAvx512(i);
  const float m = float(mass_), epsilon = p_.xsph ? float(p_.xsph_epsilon) : 0.0f;
  const bool diffusion = p_.density_diffusion != 0, liquid = s_.liquid[i];
  const float xi = s_.x[i], yi = s_.y[i], zi = s_.z[i];
  const float vxi = s_.vx[i], vyi = s_.vy[i], vzi = s_.vz[i], rhoi = s_.rho[i];
  float drho[kLanes] = {}, diffuse[kLanes] = {}, ux[kLanes] = {}, uy[kLanes] = {}, uz[kLanes] = {};
  const std::int32_t* list = list_[i];
  for (std::int32_t k = 0; k < list_count_[i]; ++k) {
    const std::size_t j = std::size_t(list[k]);
    const int l = k % kLanes;
    const float dx = xi - s_.x[j], dy = yi - s_.y[j], dz = zi - s_.z[j];
    const float r = std::sqrt(dx * dx + dy * dy + dz * dz);
    const float f = kernel_.GradientOverR(r);
    const float dvx = s_.vx[j] - vxi, dvy = s_.vy[j] - vyi, dvz = s_.vz[j] - vzi;
    drho[l] -= m * f * (dvx * dx + dvy * dy + dvz * dz);
    if (!s_.liquid[j]) continue;
    const float rhoj = s_.rho[j];
    if (diffusion) diffuse[l] += DensityDiffusionPair(rhoi, rhoj, f, m / rhoj);
    if (!liquid || epsilon == 0) continue;
    const float w = kernel_.W(r) * m / (0.5f * (rhoi + rhoj));
    ux[l] += w * dvx;
    uy[l] += w * dvy;
    uz[l] += w * dvz;
  }
  drho_[i] =
      SumLanes(drho) + 2.0f * float(p_.diffusion_delta * h_ * sound_speed_) * SumLanes(diffuse);
  if (!liquid) return;
  xsph_x_[i] = vxi + epsilon * SumLanes(ux);
  xsph_y_[i] = vyi + epsilon * SumLanes(uy);
  xsph_z_[i] = vzi + epsilon * SumLanes(uz);
}

__attribute__((target("avx512f"))) void Wcsph::DensityRateAvx512(std::size_t i) {
  const float epsilon = p_.xsph ? float(p_.xsph_epsilon) : 0.0f;
  const bool diffusion = p_.density_diffusion != 0, liquid = s_.liquid[i];
  const bool xsph = liquid && epsilon != 0;
  const __m512 m = _mm512_set1_ps(float(mass_)), half = _mm512_set1_ps(0.5f);
  const __m512 one = _mm512_set1_ps(1.0f), two = _mm512_set1_ps(2.0f), zero = _mm512_setzero_ps();
  const __m512 inverse_h = _mm512_set1_ps(kernel_.inverse_h);
  const __m512 gradient = _mm512_set1_ps(kernel_.gradient_coefficient * kernel_.inverse_h);
  const __m512 w_coefficient = _mm512_set1_ps(kernel_.w_coefficient);
  const __m512 xi = _mm512_set1_ps(s_.x[i]), yi = _mm512_set1_ps(s_.y[i]),
               zi = _mm512_set1_ps(s_.z[i]);
  const __m512 vxi = _mm512_set1_ps(s_.vx[i]), vyi = _mm512_set1_ps(s_.vy[i]),
               vzi = _mm512_set1_ps(s_.vz[i]), rhoi = _mm512_set1_ps(s_.rho[i]);
  __m512 drho = zero, diffuse = zero, ux = zero, uy = zero, uz = zero;
  const std::int32_t* list = list_[i];
  const int count = list_count_[i];
  for (int k = 0; k < count; k += kLanes) {
    const __mmask16 lanes = Lanes(count - k);
    const __m512i j = _mm512_maskz_loadu_epi32(lanes, list + k);
    const __m512 dx = _mm512_sub_ps(xi, Gather(lanes, j, s_.x)),
                 dy = _mm512_sub_ps(yi, Gather(lanes, j, s_.y)),
                 dz = _mm512_sub_ps(zi, Gather(lanes, j, s_.z));
    const __m512 r = _mm512_maskz_sqrt_ps(
        lanes, _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(dx, dx), _mm512_mul_ps(dy, dy)),
                             _mm512_mul_ps(dz, dz)));
    const __m512 q = _mm512_mul_ps(r, inverse_h);
    const __m512 u = _mm512_sub_ps(one, _mm512_mul_ps(half, q));
    const __mmask16 inside = _mm512_mask_cmp_ps_mask(lanes, q, two, _CMP_LT_OQ);
    const __m512 f = _mm512_maskz_mul_ps(inside, _mm512_mul_ps(_mm512_mul_ps(gradient, u), u), u);
    const __m512 dvx = _mm512_sub_ps(Gather(lanes, j, s_.vx), vxi),
                 dvy = _mm512_sub_ps(Gather(lanes, j, s_.vy), vyi),
                 dvz = _mm512_sub_ps(Gather(lanes, j, s_.vz), vzi);
    const __m512 dot = _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(dvx, dx), _mm512_mul_ps(dvy, dy)),
                                     _mm512_mul_ps(dvz, dz));
    drho = _mm512_mask_sub_ps(drho, lanes, drho, _mm512_mul_ps(_mm512_mul_ps(m, f), dot));
    const __m512i liquid_j =
        _mm512_mask_i32gather_epi32(_mm512_setzero_si512(), lanes, j, liquid32_.data(), 4);
    const __mmask16 of_liquid = _mm512_mask_test_epi32_mask(lanes, liquid_j, liquid_j);
    if (!of_liquid) continue;
    const __m512 rhoj = Gather(lanes, j, s_.rho);
    if (diffusion) {
      const __m512 term =
          _mm512_mul_ps(_mm512_mul_ps(_mm512_sub_ps(rhoi, rhoj), f), _mm512_div_ps(m, rhoj));
      diffuse = _mm512_mask_add_ps(diffuse, of_liquid, diffuse, term);
    }
    if (!xsph) continue;
    const __m512 u2 = _mm512_mul_ps(u, u);
    const __m512 w =
        _mm512_maskz_mul_ps(inside, _mm512_mul_ps(_mm512_mul_ps(w_coefficient, u2), u2),
                            _mm512_add_ps(_mm512_mul_ps(two, q), one));
    const __m512 weight =
        _mm512_div_ps(_mm512_mul_ps(w, m), _mm512_mul_ps(half, _mm512_add_ps(rhoi, rhoj)));
    ux = _mm512_mask_add_ps(ux, of_liquid, ux, _mm512_mul_ps(weight, dvx));
    uy = _mm512_mask_add_ps(uy, of_liquid, uy, _mm512_mul_ps(weight, dvy));
    uz = _mm512_mask_add_ps(uz, of_liquid, uz, _mm512_mul_ps(weight, dvz));
  }
  drho_[i] =
      SumLanes(drho) + 2.0f * float(p_.diffusion_delta * h_ * sound_speed_) * SumLanes(diffuse);
  if (!liquid) return;
  xsph_x_[i] = s_.vx[i] + epsilon * SumLanes(ux);
  xsph_y_[i] = s_.vy[i] + epsilon * SumLanes(uy);
  xsph_z_[i] = s_.vz[i] + epsilon * SumLanes(uz);
}

}  // namespace owval::engine::internal
