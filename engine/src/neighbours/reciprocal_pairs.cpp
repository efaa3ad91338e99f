#include "neighbours/reciprocal_pairs.hpp"

#include <vector>

namespace owval::engine::internal {
namespace {

bool Lists(const ParticleState& s, std::int32_t j, std::int32_t i) {
  const Neighbour* slots = s.slots(std::size_t(j));
  for (int n = 0; n < kSlots && slots[n].index >= 0; ++n)
    if (slots[n].index == i) return true;
  return false;
}

}  // namespace

std::size_t KeepReciprocalPairs(ParticleState* state) {
  ParticleState& s = *state;
  // Decided on the lists as the search left them, then applied: a removal must not decide another.
  std::vector<std::uint32_t> drop(s.moving.size(), 0);  // bit n: slot n goes
  for (std::size_t n = 0; n < s.moving.size(); ++n) {
    const std::int32_t i = s.moving[n];
    const Neighbour* slots = s.slots(std::size_t(i));
    for (int m = 0; m < kSlots && slots[m].index >= 0; ++m) {
      const std::int32_t j = slots[m].index;
      if (!IsBoundary(s.position[j].w) && !Lists(s, j, i)) drop[n] |= 1u << m;
    }
  }
  std::size_t removed = 0;
  for (std::size_t n = 0; n < s.moving.size(); ++n) {
    if (drop[n] == 0) continue;
    const std::int32_t i = s.moving[n];
    Neighbour* slots = s.slots(std::size_t(i));
    std::uint32_t boundary = 0;
    int kept = 0;
    for (int m = 0; m < kSlots && slots[m].index >= 0; ++m) {
      if (drop[n] >> m & 1u) continue;
      if (IsBoundary(s.position[slots[m].index].w)) boundary |= 1u << kept;
      slots[kept++] = slots[m];
    }
    removed += std::size_t(__builtin_popcount(drop[n]));
    for (int m = kept; m < kSlots; ++m) slots[m] = Neighbour{};
    if (s.boundary_slots.size() == s.size()) s.boundary_slots[std::size_t(i)] = boundary;
  }
  return removed;
}

}  // namespace owval::engine::internal
