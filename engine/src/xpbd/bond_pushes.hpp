#pragma once
// The arithmetic of one Jacobi pass of the split scheme's one-sided bonds (Xpbd::
// ProjectBondsOneSided), eight bonds at a time: per bond b of particle i with partner j, from
// the positions the pass began with,
//   d = p_i − p_j, L = |d|, Δλ = (−(L − rest) − α̃·λ_b)/(1 + α̃), λ_b += Δλ, push_b = (Δλ/L)·d,
// skipped (λ_b kept, push_b = +0) when α̃ < 0 (no stiffness) or !(L > 0) [MMC16 eqs. 17-18].
// Each lane does the scalar loop's operations in its order (no fused multiply-add), so the
// pushes are its floats bit for bit; the caller adds each row's pushes in bond order, as the
// scalar loop does (+0 for a skipped bond leaves a sum that starts at +0 unchanged).
#include <cstddef>
#include <cstdint>

#include "xpbd/projections.hpp"

namespace owval::engine::internal {

struct BondArrays {
  const float* rest_cu;
  const float* alpha_tilde;  // α̃ = α/h², or −1 for a bond without stiffness
  std::size_t count;         // a multiple of 8: bonds past the last have α̃ = −1
};

// From the offsets d = p_i − p_j (dx, dy, dz, each computed by the caller: gathers were slower
// than scalar loads on this machine's CPU), updates lambda[0, count) and overwrites dx/dy/dz with
// the pushes. Whole registers only (masked stores were slower still). Needs AVX2 and FMA
// (UseAvx2() or UseAvx512()).
void BondPushesAvx2(const BondArrays& bonds, float* lambda, float* dx, float* dy, float* dz);

}  // namespace owval::engine::internal
