#pragma once
// The inner loop of the neighbour search: of one cell's candidates (structure of arrays, in the
// cell's order), those within h of a particle, packed in the same order with their squared
// distances. Only these can enter a neighbour list (the selection's limit starts at h² and only
// falls), so the selection that follows sees exactly the sequence it would have seen.
#include <cstdint>

#include "state/particle_state.hpp"

namespace owval::engine::internal {

// Slack the output arrays need beyond n entries (the vector path stores whole registers).
constexpr int kNearSlack = 16;

struct CandidateCell {
  const std::int32_t* index;
  const float *x, *y, *z;
  int count;
};

// Writes the candidates m of cell with d² = fma(dz, dz, fma(dx, dx, dy·dy)) <= h2 (d = p − x_m,
// sphFluid.cl:311 as PoCL contracts it) and index != self into near_index/near_d2, in order, and
// returns how many. The outputs hold cell.count + kNearSlack entries. Uses AVX-512 or else AVX2
// with FMA when the running CPU has it (same operations per lane, so the same floats), scalar
// code otherwise.
int NearCandidates(const CandidateCell& cell, const float p[3], float h2, std::int32_t self,
                   std::int32_t* near_index, float* near_d2);

// The same for several cells, one after another: their candidates within h appended in the
// cells' order. The outputs hold the cells' total count + kNearSlack entries.
int NearCandidatesOfCells(const CandidateCell* cells, int cell_count, const float p[3], float h2,
                          std::int32_t self, std::int32_t* near_index, float* near_d2);

// The first index of the largest of 32 squared distances (std::max_element's answer; the values
// are never NaN). Vector code when the running CPU has AVX2 or AVX-512.
int FirstLargestOf32(const float* d2);

}  // namespace owval::engine::internal
