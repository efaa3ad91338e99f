#include "phases/pressure_force.hpp"

#include "kernels/avx512.hpp"
#include "kernels/kernels.hpp"
#include "kernels/simd.hpp"

namespace owval::engine::internal {
namespace {

struct PressureInputs {
  const SphConstants& k;
  const ParticleState& s;
  const float* density;
  float short_range_pressure;
};

// The pair term of slot m (sphFluid.cl:990-1022): below hS/4 a fixed short-range repulsion
// replaces the pressure term. ∇Wspiky's shape (h − r)²; −(a·a) and (−a)·a are the same float.
Float4 PressureAccelerationScalar(const PressureInputs& in, std::int32_t i) {
  const SphConstants& k = in.k;
  const ParticleState& s = in.s;
  const float quarter = k.hs_m / 4;
  const Float4 xi = s.position[i];
  const Neighbour* slots = s.slots(i);
  float sum[3] = {0, 0, 0};
  for (int m = 0; m < kSlots && slots[m].index >= 0; ++m) {
    const float r = slots[m].distance_m;
    if (!(r < k.hs_m)) continue;
    const std::int32_t j = slots[m].index;
    const float t = r < quarter ? -SpikyGradientShape(quarter, r) * 0.5f * in.short_range_pressure /
                                      in.density[j]
                                : -SpikyGradientShape(k.hs_m, r) * 0.5f *
                                      (s.pressure[i] + s.pressure[j]) / in.density[j];
    const Float4 xj = s.position[j];  // direction from x(t), not x* (gotcha 7)
    sum[0] += t * ((xi.x - xj.x) * k.scale) / r;
    sum[1] += t * ((xi.y - xj.y) * k.scale) / r;
    sum[2] += t * ((xi.z - xj.z) * k.scale) / r;
  }
  const float factor = k.mass_grad_wspiky / in.density[i];
  return {sum[0] * factor, sum[1] * factor, sum[2] * factor, 0};
}

// The same, the 32 pair terms formed 16 slots per instruction (each lane the scalar code's
// operations in its order; empty slots compute a throwaway term from row i), then added in slot
// order.
OWVAL_AVX512 Float4 PressureAccelerationAvx512(const PressureInputs& in, std::int32_t i) {
  const SphConstants& k = in.k;
  const ParticleState& s = in.s;
  const Float4 xi = s.position[i];
  const Neighbour* slots = s.slots(i);
  alignas(64) std::int32_t index[kSlots];
  alignas(64) float distance[kSlots], term[3][kSlots];
  int count = 0;
  for (int m = 0; m < kSlots; ++m) {
    count += slots[m].index >= 0 && count == m;
    index[m] = slots[m].index < 0 ? i : slots[m].index;
    distance[m] = slots[m].distance_m;
  }
  const float* position = &s.position[0].x;
  const __m512 quarter = _mm512_set1_ps(k.hs_m / 4), hs = _mm512_set1_ps(k.hs_m),
               half = _mm512_set1_ps(0.5f), srp = _mm512_set1_ps(in.short_range_pressure),
               pi = _mm512_set1_ps(s.pressure[i]), scale = _mm512_set1_ps(k.scale);
  const __m512 xi_axis[3] = {_mm512_set1_ps(xi.x), _mm512_set1_ps(xi.y), _mm512_set1_ps(xi.z)};
  for (int m = 0; m < kSlots; m += 16) {
    const __m512i j = _mm512_load_si512(index + m), j4 = Times4(j);
    const __m512 r = _mm512_load_ps(distance + m);
    const __m512 rho_j = Gather(j, in.density);
    const __m512 p_j = Gather(j, s.pressure.data());
    const __m512 qn = _mm512_sub_ps(quarter, r), qf = _mm512_sub_ps(hs, r);
    const __m512 shape_near = Negate(_mm512_mul_ps(qn, qn));
    const __m512 shape_far = Negate(_mm512_mul_ps(qf, qf));
    const __m512 near = _mm512_div_ps(_mm512_mul_ps(_mm512_mul_ps(shape_near, half), srp), rho_j);
    const __m512 far =
        _mm512_div_ps(_mm512_mul_ps(_mm512_mul_ps(shape_far, half), _mm512_add_ps(pi, p_j)), rho_j);
    const __m512 t = _mm512_mask_blend_ps(_mm512_cmp_ps_mask(r, quarter, _CMP_LT_OQ), far, near);
    for (int a = 0; a < 3; ++a) {
      const __m512 xj = Gather(j4, position + a);
      const __m512 d = _mm512_mul_ps(_mm512_sub_ps(xi_axis[a], xj), scale);
      _mm512_store_ps(term[a] + m, _mm512_div_ps(_mm512_mul_ps(t, d), r));
    }
  }
  float sum[3] = {0, 0, 0};
  for (int m = 0; m < count; ++m) {
    if (!(distance[m] < k.hs_m)) continue;
    sum[0] += term[0][m];
    sum[1] += term[1][m];
    sum[2] += term[2][m];
  }
  const float factor = k.mass_grad_wspiky / in.density[i];
  return {sum[0] * factor, sum[1] * factor, sum[2] * factor, 0};
}

}  // namespace

void ComputePressureAcceleration(const SphConstants& k, const ParticleState& s,
                                 const std::vector<float>& density, float short_range_pressure,
                                 std::vector<Float4>* out, int threads) {
  std::vector<Float4>& acceleration = *out;
  const PressureInputs in{k, s, density.data(), short_range_pressure};
  const bool vector = UseAvx512();
#pragma omp parallel for schedule(static) num_threads(threads)
  for (std::size_t n = 0; n < s.moving.size(); ++n) {
    const std::int32_t i = s.moving[n];
    acceleration[i] =
        vector ? PressureAccelerationAvx512(in, i) : PressureAccelerationScalar(in, i);
  }
}

}  // namespace owval::engine::internal
