#include "phases/walls.hpp"

#include <algorithm>
#include <cmath>

#include "kernels/kernels.hpp"

namespace owval::engine::internal {

void CorrectAtWalls(const SphConstants& k, const ParticleState& s, std::int32_t i, Float4* x,
                    Float4* v) {
  Float4 normal{};
  float weight_sum = 0, weighted_depth = 0;
  const Neighbour* slots = s.slots(i);
  // Only boundary slots contribute, in slot order (the list's boundary bits, from Refresh; lists
  // filled some other way have no bits, and every slot is checked).
  std::uint32_t boundary = 0;
  if (s.boundary_slots.size() == s.size()) {
    boundary = s.boundary_slots[std::size_t(i)];
  } else {
    for (int n = 0; n < kSlots && slots[n].index >= 0; ++n)
      boundary |= std::uint32_t(IsBoundary(s.position[slots[n].index].w)) << n;
  }
  for (std::uint32_t mask = boundary; mask != 0; mask &= mask - 1) {
    const std::int32_t b = slots[__builtin_ctz(mask)].index;
    const Float4& xb = s.position[b];
    const float dx = x->x - xb.x, dy = x->y - xb.y, dz = x->z - xb.z;
    const float dist = std::sqrt(Fma(dz, dz, Fma(dy, dy, dx * dx)));  // sphFluid.cl:786-789
    const float w = BoundaryWeight(k.r0_cu, dist);                    // [IAGT10] eq. 10
    const Float4& nb = s.velocity[b];  // a boundary's velocity slot holds its wall normal
    normal.x = Fma(nb.x, w, normal.x);
    normal.y = Fma(nb.y, w, normal.y);
    normal.z = Fma(nb.z, w, normal.z);
    normal.w = Fma(nb.w, w, normal.w);  // the 4th component takes part in the normalisation
    weight_sum += w;
    weighted_depth = Fma(w, k.r0_cu - dist, weighted_depth);
  }
  // OpenCL's dot() as PoCL's library computes it, unfused: (x² + y²) + (z² + w²).
  float length =
      (normal.x * normal.x + normal.y * normal.y) + (normal.z * normal.z + normal.w * normal.w);
  if (length == 0) return;
  length = std::sqrt(length);
  x->x += normal.x / length * weighted_depth / weight_sum;  // [IAGT10] eq. 11
  x->y += normal.y / length * weighted_depth / weight_sum;
  x->z += normal.z / length * weighted_depth / weight_sum;
  if (!v) return;
  // Remove the velocity into the wall along the (unnormalised) normal, then friction 0.99.
  const float into = Fma(normal.z, v->z, Fma(normal.x, v->x, normal.y * v->y));
  if (into < 0) {
    v->x = Fma(-normal.x, into, v->x);
    v->y = Fma(-normal.y, into, v->y);
    v->z = Fma(-normal.z, into, v->z);
    v->x *= 0.99f;
    v->y *= 0.99f;
    v->z *= 0.99f;
    v->w *= 0.99f;
  }
}

}  // namespace owval::engine::internal
