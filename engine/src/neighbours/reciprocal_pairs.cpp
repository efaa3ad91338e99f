#include "neighbours/reciprocal_pairs.hpp"

#include <vector>

namespace owval::engine::internal {

std::size_t KeepReciprocalPairs(ParticleState* state) {
  ParticleState& s = *state;
  // Who lists each particle, as offsets into one flat array (a counting sort of every moving
  // particle's entries by the particle listed): one pass over the lists instead of a search of
  // j's list for every entry j of i's (that was 35% of an XPBD step on demo1).
  std::vector<std::int32_t> start(s.size() + 1, 0);
  for (std::int32_t j : s.moving)
    for (int m = 0; m < kSlots && s.slots(std::size_t(j))[m].index >= 0; ++m)
      ++start[std::size_t(s.slots(std::size_t(j))[m].index) + 1];
  for (std::size_t i = 0; i < s.size(); ++i) start[i + 1] += start[i];
  std::vector<std::int32_t> listed_by(std::size_t(start.back()));
  std::vector<std::int32_t> fill(start.begin(), start.end() - 1);
  for (std::int32_t j : s.moving)
    for (int m = 0; m < kSlots && s.slots(std::size_t(j))[m].index >= 0; ++m)
      listed_by[std::size_t(fill[std::size_t(s.slots(std::size_t(j))[m].index)]++)] = j;

  // Decided on the lists as the search left them, then applied: a removal must not decide another.
  std::vector<std::int32_t> lists_me(s.size(), -1);     // j lists i when lists_me[j] == i
  std::vector<std::uint32_t> drop(s.moving.size(), 0);  // bit m: slot m goes
  for (std::size_t n = 0; n < s.moving.size(); ++n) {
    const std::int32_t i = s.moving[n];
    for (std::int32_t k = start[std::size_t(i)]; k < start[std::size_t(i) + 1]; ++k)
      lists_me[std::size_t(listed_by[std::size_t(k)])] = i;
    const Neighbour* slots = s.slots(std::size_t(i));
    for (int m = 0; m < kSlots && slots[m].index >= 0; ++m) {
      const std::int32_t j = slots[m].index;
      if (!IsBoundary(s.position[j].w) && lists_me[std::size_t(j)] != i) drop[n] |= 1u << m;
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
