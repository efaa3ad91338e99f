#pragma once
// Helpers for the AVX-512 twins of scalar kernels (kernels/simd.hpp says when they run). Each is
// exact: the same float as the scalar operation in every lane.
#include <immintrin.h>
#include <cstdint>

#define OWVAL_AVX512 __attribute__((target("avx512f")))

namespace owval::engine::internal {

// −a with its sign bit flipped, as the scalar unary minus (0 − a would turn −0 into +0).
OWVAL_AVX512 inline __m512 Negate(__m512 a) {
  return _mm512_castsi512_ps(
      _mm512_xor_si512(_mm512_castps_si512(a), _mm512_set1_epi32(std::int32_t(0x80000000u))));
}

// base[index[lane]] for 16 lanes, index in elements of 4 bytes. (GCC 12's unmasked gather and
// shift intrinsics warn about their own undefined operands, hence the masked forms.)
OWVAL_AVX512 inline __m512 Gather(__m512i index, const float* base) {
  return _mm512_mask_i32gather_ps(_mm512_setzero_ps(), __mmask16(0xFFFF), index, base, 4);
}

// 4·index: the element index of component 0 of row index in an array of Float4.
OWVAL_AVX512 inline __m512i Times4(__m512i index) {
  const __m512i twice = _mm512_add_epi32(index, index);
  return _mm512_add_epi32(twice, twice);
}

}  // namespace owval::engine::internal
