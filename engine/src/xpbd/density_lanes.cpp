#include "xpbd/density_lanes.hpp"

#include <immintrin.h>

#include <cstddef>

#include "kernels/point_lanes.hpp"

namespace owval::engine::internal {
namespace {

__attribute__((target("avx2,fma"))) inline __m256i ToVector(const std::int32_t v[8]) {
  return _mm256_setr_epi32(v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7]);
}

__attribute__((target("avx2,fma"))) inline __m256 Gather(const float* values,
                                                         const std::int32_t index[8]) {
  return _mm256_setr_ps(values[index[0]], values[index[1]], values[index[2]], values[index[3]],
                        values[index[4]], values[index[5]], values[index[6]], values[index[7]]);
}

// Slot m of each lane's list (`slot_index`: the lanes' neighbour-list entries for slot 0, in
// ints): the neighbours (0 where the slot is empty) and the masks "listed" and "listed and
// moving".
__attribute__((target("avx2,fma"))) void Slot(const DensityLanes& in, __m256i slot_index, int m,
                                              __m256i* neighbour, __m256* listed, __m256* moving) {
  static_assert(sizeof(Neighbour) == 2 * sizeof(std::int32_t) && offsetof(Neighbour, index) == 0);
  const __m256i j =
      _mm256_i32gather_epi32(reinterpret_cast<const int*>(in.neighbours),
                             _mm256_add_epi32(slot_index, _mm256_set1_epi32(2 * m)), 4);
  const __m256i yes = _mm256_cmpgt_epi32(j, _mm256_set1_epi32(-1));
  *neighbour = _mm256_and_si256(j, yes);
  *listed = _mm256_castsi256_ps(yes);
  // A block of moving particles needs no second gather: it waits on the first, and the two
  // took a third of this function's samples.
  const __m256i moving_j =
      in.moving_end > in.moving_first
          ? _mm256_and_si256(_mm256_cmpgt_epi32(j, _mm256_set1_epi32(in.moving_first - 1)),
                             _mm256_cmpgt_epi32(_mm256_set1_epi32(in.moving_end), j))
          : _mm256_i32gather_epi32(in.moving, *neighbour, 4);
  *moving = _mm256_castsi256_ps(_mm256_and_si256(yes, moving_j));
}

__attribute__((target("avx2,fma"))) inline void Load(const DensityLanes& in,
                                                     const std::int32_t index[8], __m256* x,
                                                     __m256* y, __m256* z) {
  const float* at[8];
  for (int l = 0; l < 8; ++l)
    at[l] = index[l] == in.last ? in.last_point : in.points + 3 * std::size_t(index[l]);
  LoadPoints(at, x, y, z);
}

__attribute__((target("avx2,fma"))) __m256 Add(__m256 sum, __m256 term, __m256 mask) {
  return _mm256_blendv_ps(sum, _mm256_add_ps(sum, term), mask);
}

// (a·a + b·b) + c·c, each product rounded, as Norm and the scalar loop's squares.
__attribute__((target("avx2,fma"))) __m256 Squares(__m256 a, __m256 b, __m256 c) {
  return _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(a, a), _mm256_mul_ps(b, b)),
                       _mm256_mul_ps(c, c));
}

}  // namespace

__attribute__((target("avx2,fma"))) int DensityConstraintAvx2(const DensityLanes& in,
                                                              const std::int32_t particle[8],
                                                              float w_out[8], float norm2_out[8],
                                                              float* record,
                                                              float tensile_out[3][8]) {
  const DensityKernel<float>& k = in.kernel;
  const __m256 zero = _mm256_setzero_ps(), h = _mm256_set1_ps(k.h), h2 = _mm256_set1_ps(k.h2);
  const __m256 poly6 = _mm256_set1_ps(k.poly6);
  const __m256 coefficient = _mm256_set1_ps(k.rest_volume * k.spiky_gradient);
  __m256 xi, yi, zi;
  Load(in, particle, &xi, &yi, &zi);
  __m256 w = _mm256_set1_ps(k.W(0)), norm2 = zero, gx = zero, gy = zero, gz = zero;
  const TensileCorrection<float>& s = in.tensile;
  const __m256 inverse_w_dq = _mm256_set1_ps(s.inverse_w_dq),
               minus_strength = _mm256_set1_ps(-s.strength);
  __m256 tx = zero, ty = zero, tz = zero;
  const __m256i slot_index =
      _mm256_slli_epi32(_mm256_mullo_epi32(ToVector(particle), _mm256_set1_epi32(kSlots)), 1);
  int m = 0;
  for (; m < kSlots; ++m) {
    __m256i neighbour;
    __m256 listed, moving;
    Slot(in, slot_index, m, &neighbour, &listed, &moving);
    if (_mm256_testz_ps(listed, listed)) break;  // no lane has a slot m
    float* slot = record + std::size_t(m) * kRecord;
    // The moving neighbour, −1 for a fixed one, −2 for an empty slot.
    const __m256i code =
        _mm256_blendv_epi8(_mm256_blendv_epi8(_mm256_set1_epi32(-2), _mm256_set1_epi32(-1),
                                              _mm256_castps_si256(listed)),
                           neighbour, _mm256_castps_si256(moving));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(slot), code);
    std::int32_t j[8];
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(j), neighbour);
    __m256 xj, yj, zj;
    Load(in, j, &xj, &yj, &zj);
    const __m256 dx = _mm256_sub_ps(xi, xj), dy = _mm256_sub_ps(yi, yj), dz = _mm256_sub_ps(zi, zj);
    const __m256 r2 = Squares(dx, dy, dz);
    const __m256 q = _mm256_sub_ps(h2, r2);  // W: poly6·q·q·q inside the support, else +0
    const __m256 wj = _mm256_and_ps(_mm256_cmp_ps(r2, h2, _CMP_LT_OQ),
                                    _mm256_mul_ps(_mm256_mul_ps(_mm256_mul_ps(poly6, q), q), q));
    w = Add(w, wj, listed);
    // Gradient: f = V0·spiky·(h − r)·(h − r)/r for 0 < r < h, else the zero vector.
    const __m256 r = _mm256_sqrt_ps(r2), hr = _mm256_sub_ps(h, r);
    const __m256 inside =
        _mm256_and_ps(_mm256_cmp_ps(r, zero, _CMP_GT_OQ), _mm256_cmp_ps(r, h, _CMP_LT_OQ));
    const __m256 f = _mm256_div_ps(_mm256_mul_ps(_mm256_mul_ps(coefficient, hr), hr), r);
    const __m256 gxj = _mm256_and_ps(inside, _mm256_mul_ps(f, dx));
    const __m256 gyj = _mm256_and_ps(inside, _mm256_mul_ps(f, dy));
    const __m256 gzj = _mm256_and_ps(inside, _mm256_mul_ps(f, dz));
    _mm256_storeu_ps(slot + 8, gxj);
    _mm256_storeu_ps(slot + 16, gyj);
    _mm256_storeu_ps(slot + 24, gzj);
    gx = Add(gx, gxj, listed), gy = Add(gy, gyj, listed), gz = Add(gz, gzj, listed);
    norm2 = Add(norm2, Squares(gxj, gyj, gzj), moving);
    if (s.on()) {  // TensileCorrection::Of, then its pair's term, as the scalar loop
      const __m256 ratio = _mm256_mul_ps(wj, inverse_w_dq);
      __m256 power = ratio;
      for (int e = 1; e < s.exponent; ++e) power = _mm256_mul_ps(power, ratio);
      const __m256 s_corr = _mm256_mul_ps(minus_strength, power);
      tx = Add(tx, _mm256_mul_ps(s_corr, gxj), listed);
      ty = Add(ty, _mm256_mul_ps(s_corr, gyj), listed);
      tz = Add(tz, _mm256_mul_ps(s_corr, gzj), listed);
    }
  }
  _mm256_storeu_ps(w_out, w);
  _mm256_storeu_ps(norm2_out, _mm256_add_ps(norm2, Squares(gx, gy, gz)));
  if (s.on()) {
    _mm256_storeu_ps(tensile_out[0], tx);
    _mm256_storeu_ps(tensile_out[1], ty);
    _mm256_storeu_ps(tensile_out[2], tz);
  }
  return m;
}

__attribute__((target("avx2,fma"))) void DensityDisplacementAvx2(const std::int32_t particle[8],
                                                                 const float* dlambda,
                                                                 const float* record, int slots,
                                                                 float dp[3][8]) {
  const __m256 own = Gather(dlambda, particle);
  __m256 dx = _mm256_setzero_ps(), dy = dx, dz = dx;
  for (int m = 0; m < slots; ++m) {
    const float* slot = record + std::size_t(m) * kRecord;
    const __m256i code = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(slot));
    const __m256i moving = _mm256_cmpgt_epi32(code, _mm256_set1_epi32(-1));
    const __m256 listed = _mm256_castsi256_ps(_mm256_cmpgt_epi32(code, _mm256_set1_epi32(-2)));
    std::int32_t j[8];
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(j), _mm256_and_si256(code, moving));
    // Δλ_i + (moving ? Δλ_j : 0)
    const __m256 lambda =
        _mm256_add_ps(own, _mm256_and_ps(_mm256_castsi256_ps(moving), Gather(dlambda, j)));
    dx = Add(dx, _mm256_mul_ps(lambda, _mm256_loadu_ps(slot + 8)), listed);
    dy = Add(dy, _mm256_mul_ps(lambda, _mm256_loadu_ps(slot + 16)), listed);
    dz = Add(dz, _mm256_mul_ps(lambda, _mm256_loadu_ps(slot + 24)), listed);
  }
  _mm256_storeu_ps(dp[0], dx);
  _mm256_storeu_ps(dp[1], dy);
  _mm256_storeu_ps(dp[2], dz);
}

}  // namespace owval::engine::internal
