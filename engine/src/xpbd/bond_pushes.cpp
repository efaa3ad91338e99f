#include "xpbd/bond_pushes.hpp"

#include <immintrin.h>

namespace owval::engine::internal {

__attribute__((target("avx2,fma"))) void BondPushesAvx2(const BondArrays& bonds, float* lambda,
                                                        float* dx_out, float* dy_out,
                                                        float* dz_out) {
  const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.0f);
  const __m256 sign = _mm256_set1_ps(-0.0f);
  for (std::size_t b = 0; b < bonds.count; b += 8) {
    const __m256 dx = _mm256_loadu_ps(dx_out + b), dy = _mm256_loadu_ps(dy_out + b),
                 dz = _mm256_loadu_ps(dz_out + b);
    // Norm: (d0·d0 + d1·d1) + d2·d2, each product rounded.
    const __m256 length = _mm256_sqrt_ps(_mm256_add_ps(
        _mm256_add_ps(_mm256_mul_ps(dx, dx), _mm256_mul_ps(dy, dy)), _mm256_mul_ps(dz, dz)));
    const __m256 alpha = _mm256_loadu_ps(bonds.alpha_tilde + b);
    const __m256 rest = _mm256_loadu_ps(bonds.rest_cu + b);
    const __m256 old_lambda = _mm256_loadu_ps(lambda + b);
    const __m256 taken = _mm256_and_ps(_mm256_cmp_ps(alpha, zero, _CMP_NLT_UQ),   // !(α̃ < 0)
                                       _mm256_cmp_ps(length, zero, _CMP_GT_OQ));  // L > 0
    const __m256 numerator = _mm256_sub_ps(_mm256_xor_ps(_mm256_sub_ps(length, rest), sign),
                                           _mm256_mul_ps(alpha, old_lambda));
    const __m256 dlambda = _mm256_div_ps(numerator, _mm256_add_ps(one, alpha));
    _mm256_storeu_ps(lambda + b,
                     _mm256_blendv_ps(old_lambda, _mm256_add_ps(old_lambda, dlambda), taken));
    const __m256 step = _mm256_div_ps(dlambda, length);
    _mm256_storeu_ps(dx_out + b, _mm256_and_ps(taken, _mm256_mul_ps(step, dx)));
    _mm256_storeu_ps(dy_out + b, _mm256_and_ps(taken, _mm256_mul_ps(step, dy)));
    _mm256_storeu_ps(dz_out + b, _mm256_and_ps(taken, _mm256_mul_ps(step, dz)));
  }
}

}  // namespace owval::engine::internal
