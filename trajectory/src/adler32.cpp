#include "adler32.hpp"

#include <zlib.h>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

namespace owval::internal {
#if defined(__x86_64__)
namespace {

constexpr std::uint32_t kBase = 65521;  // largest prime below 2^16
// Bytes per reduction: zlib's NMAX (the most before s2 can overflow 32 bits), in whole 32-byte
// blocks.
constexpr std::size_t kBlockRun = 5552 / 32 * 32;

std::uint32_t HorizontalSum(__m256i v) __attribute__((target("avx2")));
std::uint32_t HorizontalSum(__m256i v) {
  __m128i s = _mm_add_epi32(_mm256_castsi256_si128(v), _mm256_extracti128_si256(v, 1));
  s = _mm_add_epi32(s, _mm_shuffle_epi32(s, _MM_SHUFFLE(1, 0, 3, 2)));
  s = _mm_add_epi32(s, _mm_shuffle_epi32(s, _MM_SHUFFLE(2, 3, 0, 1)));
  return std::uint32_t(_mm_cvtsi128_si32(s));
}

// For a run of 32-byte blocks starting with sums (s1, s2): s1 gains every byte; s2 gains, per
// block, 32·(s1 before the block) plus the bytes weighted 32, 31, ..., 1.
std::uint32_t Adler32Avx2(std::uint32_t adler, const unsigned char* data, std::size_t length)
    __attribute__((target("avx2")));
std::uint32_t Adler32Avx2(std::uint32_t adler, const unsigned char* data, std::size_t length) {
  std::uint32_t s1 = adler & 0xffff, s2 = adler >> 16;
  const __m256i weights =
      _mm256_setr_epi8(32, 31, 30, 29, 28, 27, 26, 25, 24, 23, 22, 21, 20, 19, 18, 17, 16, 15, 14,
                       13, 12, 11, 10, 9, 8, 7, 6, 5, 4, 3, 2, 1);
  const __m256i ones = _mm256_set1_epi16(1), zero = _mm256_setzero_si256();
  while (length >= 32) {
    const std::size_t run = length < kBlockRun ? length / 32 * 32 : kBlockRun;
    __m256i v1 = _mm256_zextsi128_si256(_mm_cvtsi32_si128(int(s1)));
    __m256i v2 = _mm256_zextsi128_si256(_mm_cvtsi32_si128(int(s2)));
    __m256i v1_before_blocks = zero;  // Σ over blocks of s1 before the block
    for (std::size_t done = 0; done < run; done += 32, data += 32) {
      const __m256i bytes = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(data));
      v1_before_blocks = _mm256_add_epi32(v1_before_blocks, v1);
      v1 = _mm256_add_epi32(v1, _mm256_sad_epu8(bytes, zero));
      v2 = _mm256_add_epi32(v2, _mm256_madd_epi16(_mm256_maddubs_epi16(bytes, weights), ones));
    }
    v2 = _mm256_add_epi32(v2, _mm256_slli_epi32(v1_before_blocks, 5));
    s1 = HorizontalSum(v1) % kBase;
    s2 = HorizontalSum(v2) % kBase;
    length -= run;
  }
  return std::uint32_t(adler32(uLong((s2 << 16) | s1), data, uInt(length)));
}

}  // namespace
#endif

std::uint32_t Adler32(std::uint32_t adler, const unsigned char* data, std::size_t length) {
#if defined(__x86_64__)
  static const bool avx2 = (__builtin_cpu_init(), __builtin_cpu_supports("avx2"));
  if (avx2) return Adler32Avx2(adler, data, length);
#endif
  return std::uint32_t(adler32_z(adler, data, length));
}

}  // namespace owval::internal
