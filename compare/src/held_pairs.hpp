#pragma once
// How close a pair of particles is HELD: for each kind of pair (elastic-elastic, elastic-liquid,
// elastic-boundary, liquid-liquid, liquid-boundary; two boundary particles are built, not
// simulated), the smallest distance within which some pair stays for `hold_frames` consecutive
// paired frames. The closest approach (closest_approach.hpp) is the rarest brief encounter; this
// is its held counterpart: an honest near-encounter lasts a frame or two, while a constraint that
// leaks, a liquid particle stuck in the body wall, or a particle edited onto another holds its
// pair close for the rest of the run. Sibernetic's own demo1 liquid, compressed under the cube,
// holds pairs at a quarter of r0 for tens of milliseconds, so the gate compares the candidate's
// held distance with the reference's, kind by kind (docs/checklist.md, "held_pair").
//
// Streaming: only pairs currently within `cap_cu` are kept (a hash map bounded by the moving
// particles' neighbours), each with its run length at a ladder of distances cap·2^(-j/8), so
// memory is bounded by particles, never by run length; the held distance is a ladder level
// (a factor 2^(1/8) = 1.09 apart).
#include <array>
#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "closest_approach.hpp"
#include "owval/trajectory/frame_source.hpp"

namespace owval::compare::internal {

// The median over `moving` of the distance to the nearest other particle: the scene's spacing
// (Sibernetic places particles r0 apart). Searches from `start_cu`, doubling. 0 when `moving` is
// empty or no particle has a neighbour. With `among_themselves`, only the other particles of
// `moving` count as neighbours (an elastic body's own lattice, not the liquid beside it).
double MedianNearestSpacing(const FrameRef& frame, const std::vector<std::size_t>& moving,
                            double start_cu, bool among_themselves = false);

// The five kinds of pair that are gated, in this order.
constexpr int kPairKinds = 5;
const char* PairKindName(int pair_kind);  // "elastic-liquid"

class HeldPairs {
 public:
  static constexpr int kLevelsPerOctave = 8;
  static constexpr int kLevels = 12 * kLevelsPerOctave;  // down to cap / 4096

  struct Held {
    int level = -1;  // the deepest ladder level some pair held for hold_frames; -1: none
    std::size_t first = 0, second = 0;
    std::size_t end_pair = 0;  // the paired frame (its index) at which the hold reached its length
  };

  HeldPairs(double cap_cu, std::size_t hold_frames) : cap_cu_(cap_cu), hold_frames_(hold_frames) {}

  // Paired frame number `pair_index` (consecutive from 0) of this run. Returns the frame's
  // closest pair when it lies within the cap (infinite distance otherwise), which the
  // closest_approach gate then need not search for again.
  ClosestPair Observe(const FrameRef& frame, const std::vector<std::size_t>& moving,
                      std::size_t pair_index);

  double LevelDistanceCu(int level) const;  // cap·2^(-level/8); cap for level -1
  const std::array<Held, kPairKinds>& held() const { return held_; }
  std::size_t hold_frames() const { return hold_frames_; }
  double cap_cu() const { return cap_cu_; }

 private:
  struct Streak {
    std::size_t last_pair = 0;
    std::array<std::uint32_t, kLevels> run{};  // consecutive paired frames within each level
  };
  void Update(std::size_t first, std::size_t second, double distance_cu, int pair_kind,
              std::size_t pair_index);

  double cap_cu_;
  std::size_t hold_frames_;
  std::size_t particles_ = 0;
  std::unordered_map<std::uint64_t, Streak> streaks_;  // pairs within cap at the last frame
  std::array<Held, kPairKinds> held_{};
};

}  // namespace owval::compare::internal
