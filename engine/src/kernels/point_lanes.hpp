#pragma once
// Loading eight three-float points into three vectors of x, y and z, for the float solver's
// 8-lane paths (xpbd/bond_pushes.cpp, xpbd/density_lanes.cpp, phases/membranes.cpp).
#include <immintrin.h>

#include <cstdint>

namespace owval::engine::internal {

__attribute__((target("avx2,fma"))) inline __m256 TwoPoints(const float* low, const float* high) {
  return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(low)), _mm_loadu_ps(high), 1);
}

// Eight points' x, y and z by one 16-byte load per point (its x, y, z and the float after it)
// and a 4 × 4 transpose in each half: cheaper on this machine's CPU than scalar loads or vector
// gathers. Each address must have one readable float after its point.
__attribute__((target("avx2,fma"))) inline void LoadPoints(const float* const at[8], __m256* x,
                                                           __m256* y, __m256* z) {
  const __m256 r04 = TwoPoints(at[0], at[4]), r15 = TwoPoints(at[1], at[5]);
  const __m256 r26 = TwoPoints(at[2], at[6]), r37 = TwoPoints(at[3], at[7]);
  const __m256 xy01 = _mm256_unpacklo_ps(r04, r15), zw01 = _mm256_unpackhi_ps(r04, r15);
  const __m256 xy23 = _mm256_unpacklo_ps(r26, r37), zw23 = _mm256_unpackhi_ps(r26, r37);
  *x = _mm256_shuffle_ps(xy01, xy23, _MM_SHUFFLE(1, 0, 1, 0));
  *y = _mm256_shuffle_ps(xy01, xy23, _MM_SHUFFLE(3, 2, 3, 2));
  *z = _mm256_shuffle_ps(zw01, zw23, _MM_SHUFFLE(1, 0, 1, 0));
}

// The same for points[index[l]] of an array with one readable float after its last point.
__attribute__((target("avx2,fma"))) inline void LoadPoints(const float* points,
                                                           const std::int32_t* index, __m256* x,
                                                           __m256* y, __m256* z) {
  const float* at[8];
  for (int l = 0; l < 8; ++l) at[l] = points + 3 * index[l];
  LoadPoints(at, x, y, z);
}

}  // namespace owval::engine::internal
