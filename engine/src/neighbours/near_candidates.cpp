#include "neighbours/near_candidates.hpp"

#include <immintrin.h>

#include <algorithm>

#include "kernels/fma.hpp"
#include "kernels/simd.hpp"

namespace owval::engine::internal {
namespace {

int NearScalar(const CandidateCell& cell, const float p[3], float h2, std::int32_t self,
               std::int32_t* near_index, float* near_d2) {
  int near = 0;
  for (int m = 0; m < cell.count; ++m) {
    const float dx = p[0] - cell.x[m], dy = p[1] - cell.y[m], dz = p[2] - cell.z[m];
    const float d2 = Fma(dz, dz, Fma(dx, dx, dy * dy));
    near_d2[near] = d2;
    near_index[near] = cell.index[m];
    near += int(d2 <= h2) & int(cell.index[m] != self);  // no branch: most candidates fail
  }
  return near;
}

// Sixteen candidates per iteration; the packed lanes are compressed in a register and stored
// whole (a compressing store to memory is slow on some CPUs), hence kNearSlack. The particle's
// registers are set once for all its cells.
struct Avx512Particle {
  __m512 px, py, pz, limit;
  __m512i me;
};

__attribute__((target("avx512f"))) Avx512Particle Avx512ParticleOf(const float p[3], float h2,
                                                                   std::int32_t self) {
  return {_mm512_set1_ps(p[0]), _mm512_set1_ps(p[1]), _mm512_set1_ps(p[2]), _mm512_set1_ps(h2),
          _mm512_set1_epi32(self)};
}

__attribute__((target("avx512f"))) inline int NearCell(const CandidateCell& cell,
                                                       const Avx512Particle& q,
                                                       std::int32_t* near_index, float* near_d2) {
  const __m512 px = q.px, py = q.py, pz = q.pz, limit = q.limit;
  const __m512i me = q.me;
  int near = 0;
  for (int m = 0; m < cell.count; m += 16) {
    const int left = cell.count - m;
    const __mmask16 lanes = left >= 16 ? __mmask16(0xFFFF) : __mmask16((1u << left) - 1);
    const __m512 dx = _mm512_sub_ps(px, _mm512_maskz_loadu_ps(lanes, cell.x + m));
    const __m512 dy = _mm512_sub_ps(py, _mm512_maskz_loadu_ps(lanes, cell.y + m));
    const __m512 dz = _mm512_sub_ps(pz, _mm512_maskz_loadu_ps(lanes, cell.z + m));
    const __m512 d2 = _mm512_fmadd_ps(dz, dz, _mm512_fmadd_ps(dx, dx, _mm512_mul_ps(dy, dy)));
    const __m512i index = _mm512_maskz_loadu_epi32(lanes, cell.index + m);
    const __mmask16 within = _mm512_mask_cmp_ps_mask(lanes, d2, limit, _CMP_LE_OQ);
    const __mmask16 take = _mm512_mask_cmpneq_epi32_mask(within, index, me);
    _mm512_storeu_ps(near_d2 + near, _mm512_maskz_compress_ps(take, d2));
    _mm512_storeu_si512(near_index + near, _mm512_maskz_compress_epi32(take, index));
    near += __builtin_popcount(take);
  }
  return near;
}

__attribute__((target("avx512f"))) int NearAvx512(const CandidateCell& cell, const float p[3],
                                                  float h2, std::int32_t self,
                                                  std::int32_t* near_index, float* near_d2) {
  return NearCell(cell, Avx512ParticleOf(p, h2, self), near_index, near_d2);
}

__attribute__((target("avx512f"))) int NearCellsAvx512(const CandidateCell* cells, int cell_count,
                                                       const float p[3], float h2,
                                                       std::int32_t self, std::int32_t* near_index,
                                                       float* near_d2) {
  const Avx512Particle q = Avx512ParticleOf(p, h2, self);
  int near = 0;
  for (int c = 0; c < cell_count; ++c)
    near += NearCell(cells[c], q, near_index + near, near_d2 + near);
  return near;
}

// The 8-lane path for CPUs with AVX2 and FMA but not AVX-512: the same operations per lane. AVX2
// has no compressing store, so the kept lanes are packed by a permutation looked up by their
// mask (kept lanes first, in order) and the whole register is stored, as above.
struct PackTable {
  alignas(32) std::int32_t lanes[256][8];
  constexpr PackTable() : lanes{} {
    for (int mask = 0; mask < 256; ++mask) {
      int kept = 0;
      for (int lane = 0; lane < 8; ++lane)
        if (mask & (1 << lane)) lanes[mask][kept++] = lane;
      for (int rest = kept; rest < 8; ++rest) lanes[mask][rest] = 0;
    }
  }
};
constexpr PackTable kPack;

struct Avx2Particle {
  __m256 px, py, pz, limit;
  __m256i me;
};

__attribute__((target("avx2,fma"))) Avx2Particle Avx2ParticleOf(const float p[3], float h2,
                                                                std::int32_t self) {
  return {_mm256_set1_ps(p[0]), _mm256_set1_ps(p[1]), _mm256_set1_ps(p[2]), _mm256_set1_ps(h2),
          _mm256_set1_epi32(self)};
}

__attribute__((target("avx2,fma"))) inline int NearCellAvx2(const CandidateCell& cell,
                                                            const Avx2Particle& q,
                                                            std::int32_t* near_index,
                                                            float* near_d2) {
  const __m256i lane_number = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  int near = 0;
  for (int m = 0; m < cell.count; m += 8) {
    // Lanes past the cell's end are neither read (masked loads do not fault) nor kept.
    const __m256i lanes = _mm256_cmpgt_epi32(_mm256_set1_epi32(cell.count - m), lane_number);
    const __m256 dx = _mm256_sub_ps(q.px, _mm256_maskload_ps(cell.x + m, lanes));
    const __m256 dy = _mm256_sub_ps(q.py, _mm256_maskload_ps(cell.y + m, lanes));
    const __m256 dz = _mm256_sub_ps(q.pz, _mm256_maskload_ps(cell.z + m, lanes));
    const __m256 d2 = _mm256_fmadd_ps(dz, dz, _mm256_fmadd_ps(dx, dx, _mm256_mul_ps(dy, dy)));
    const __m256i index = _mm256_maskload_epi32(cell.index + m, lanes);
    const __m256i not_self =
        _mm256_xor_si256(_mm256_cmpeq_epi32(index, q.me), _mm256_set1_epi32(-1));
    const __m256 within = _mm256_cmp_ps(d2, q.limit, _CMP_LE_OQ);
    const int take = _mm256_movemask_ps(
        _mm256_and_ps(within, _mm256_castsi256_ps(_mm256_and_si256(lanes, not_self))));
    const __m256i pack = _mm256_load_si256(reinterpret_cast<const __m256i*>(kPack.lanes[take]));
    _mm256_storeu_ps(near_d2 + near, _mm256_permutevar8x32_ps(d2, pack));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(near_index + near),
                        _mm256_permutevar8x32_epi32(index, pack));
    near += __builtin_popcount(unsigned(take));
  }
  return near;
}

__attribute__((target("avx2,fma"))) int NearAvx2(const CandidateCell& cell, const float p[3],
                                                 float h2, std::int32_t self,
                                                 std::int32_t* near_index, float* near_d2) {
  return NearCellAvx2(cell, Avx2ParticleOf(p, h2, self), near_index, near_d2);
}

__attribute__((target("avx2,fma"))) int NearCellsAvx2(const CandidateCell* cells, int cell_count,
                                                      const float p[3], float h2, std::int32_t self,
                                                      std::int32_t* near_index, float* near_d2) {
  const Avx2Particle q = Avx2ParticleOf(p, h2, self);
  int near = 0;
  for (int c = 0; c < cell_count; ++c)
    near += NearCellAvx2(cells[c], q, near_index + near, near_d2 + near);
  return near;
}

int FirstLargestScalar(const float* d2) { return int(std::max_element(d2, d2 + kSlots) - d2); }

// Four 8-lane registers (GCC 12's 512-bit max and reduction intrinsics warn about their own
// undefined operands): the largest value by a max tree, then the first lane equal to it. AVX
// only, so both vector paths use it.
__attribute__((target("avx2"))) int FirstLargestVector(const float* d2) {
  const __m256 a = _mm256_loadu_ps(d2), b = _mm256_loadu_ps(d2 + 8), c = _mm256_loadu_ps(d2 + 16),
               d = _mm256_loadu_ps(d2 + 24);
  __m256 m = _mm256_max_ps(_mm256_max_ps(a, b), _mm256_max_ps(c, d));
  m = _mm256_max_ps(m, _mm256_permute2f128_ps(m, m, 1));
  m = _mm256_max_ps(m, _mm256_permute_ps(m, 0b01001110));
  m = _mm256_max_ps(m, _mm256_permute_ps(m, 0b10110001));
  const unsigned at = unsigned(_mm256_movemask_ps(_mm256_cmp_ps(a, m, _CMP_EQ_OQ))) |
                      unsigned(_mm256_movemask_ps(_mm256_cmp_ps(b, m, _CMP_EQ_OQ))) << 8 |
                      unsigned(_mm256_movemask_ps(_mm256_cmp_ps(c, m, _CMP_EQ_OQ))) << 16 |
                      unsigned(_mm256_movemask_ps(_mm256_cmp_ps(d, m, _CMP_EQ_OQ))) << 24;
  return __builtin_ctz(at);
}

}  // namespace

int NearCandidates(const CandidateCell& cell, const float p[3], float h2, std::int32_t self,
                   std::int32_t* near_index, float* near_d2) {
  if (UseAvx512()) return NearAvx512(cell, p, h2, self, near_index, near_d2);
  if (UseAvx2()) return NearAvx2(cell, p, h2, self, near_index, near_d2);
  return NearScalar(cell, p, h2, self, near_index, near_d2);
}

int NearCandidatesOfCells(const CandidateCell* cells, int cell_count, const float p[3], float h2,
                          std::int32_t self, std::int32_t* near_index, float* near_d2) {
  if (UseAvx512()) return NearCellsAvx512(cells, cell_count, p, h2, self, near_index, near_d2);
  if (UseAvx2()) return NearCellsAvx2(cells, cell_count, p, h2, self, near_index, near_d2);
  int near = 0;
  for (int c = 0; c < cell_count; ++c)
    near += NearScalar(cells[c], p, h2, self, near_index + near, near_d2 + near);
  return near;
}

int FirstLargestOf32(const float* d2) {
  static_assert(kSlots == 32);
  return UseAvx512() || UseAvx2() ? FirstLargestVector(d2) : FirstLargestScalar(d2);
}

}  // namespace owval::engine::internal
