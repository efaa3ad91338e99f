#pragma once
// The density projection's two neighbour loops (Xpbd<float>::ProjectDensity) for eight moving
// particles at a time, one per lane, slot by slot: each lane does the scalar loops' operations
// in their order (no fused multiply-add; a slot past a lane's list or a term the scalar code
// skips leaves the lane's sums untouched), so the floats are the scalar loops' bit for bit.
// Need AVX2 and FMA (UseAvx2() or UseAvx512()). [MM13 eqs. 1-12], kernels as projections.hpp.
#include <cstdint>

#include "state/particle_state.hpp"
#include "xpbd/projections.hpp"

namespace owval::engine::internal {

struct DensityLanes {
  const float* points;          // p: x, y, z per particle
  std::int32_t last;            // the last particle: its point is read from last_point
  const float* last_point;      // its x, y, z and a fourth float (16-byte loads)
  const Neighbour* neighbours;  // kSlots per particle, empty slots (−1) at the end
  const std::int32_t* moving;   // per particle: −1 moving, 0 fixed
  DensityKernel<float> kernel;
  TensileCorrection<float> tensile;  // [MM13]'s s_corr, or off
  // The moving particles [moving_first, moving_end) when they are one block of the
  // configuration (a neighbour is then tested by two compares), or moving_end = moving_first
  // (the table `moving` is gathered).
  std::int32_t moving_first = 0, moving_end = 0;
};

// A group's record per slot, kRecord floats: the lanes' neighbours as ints (the index of a
// moving one, −1 for a fixed one, −2 for an empty slot), then V0∇W(p_i − p_j) by axis, eight
// lanes each.
constexpr int kRecord = 32;

// Particles `particle[0..8)`: per lane w = W(0) + Σ_j W(|p_i − p_j|) and norm2 = Σ_{j moving}
// |∇_j C_i|² + |∇_i C_i|², and each slot's record into `record` (kSlots × kRecord floats); when
// in.tensile is on, also tensile[axis][lane] = Σ_j s_corr(W(|p_i − p_j|))·V0∇W(p_i − p_j).
// Returns the slots used (the longest lane's list).
int DensityConstraintAvx2(const DensityLanes& in, const std::int32_t particle[8], float w[8],
                          float norm2[8], float* record, float tensile[3][8]);

// Per lane Δp_i = Σ_j (Δλ_i + [j moving]·Δλ_j)·V0∇W(p_i − p_j), from DensityConstraintAvx2's
// record of the same particles and its slot count.
void DensityDisplacementAvx2(const std::int32_t particle[8], const float* dlambda,
                             const float* record, int slots, float dp[3][8]);

}  // namespace owval::engine::internal
