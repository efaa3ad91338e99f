#include "held_pairs.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace owval::compare::internal {
namespace {

int KindIndex(float type) {
  switch (KindOf(type)) {
    case ParticleKind::kElastic:
      return 0;
    case ParticleKind::kLiquid:
      return 1;
    default:
      return 2;
  }
}

// elastic-elastic 0, elastic-liquid 1, elastic-boundary 2, liquid-liquid 3, liquid-boundary 4.
int PairKind(float a, float b) {
  int i = KindIndex(a), j = KindIndex(b);
  if (i > j) std::swap(i, j);
  return i == 0 ? j : 2 + j;  // i is elastic or liquid: one of the two moves
}

}  // namespace

double MedianNearestSpacing(const FrameRef& f, const std::vector<std::size_t>& moving,
                            double start_cu, bool among_themselves) {
  if (moving.empty()) return 0;
  const Trajectory& t = f.trajectory;
  std::vector<double> nearest(t.particle_count(), std::numeric_limits<double>::infinity());
  std::vector<char> member(among_themselves ? t.particle_count() : 0, 0);
  if (among_themselves)
    for (std::size_t i : moving) member[i] = 1;
  if (!(start_cu > 0)) start_cu = 1;
  // Once half the moving particles have a neighbour within the radius, the median is among them
  // (every other one's nearest lies farther). Forty doublings reach any finite box.
  for (int widen = 0; widen < 40; ++widen, start_cu *= 2) {
    ForEachPairWithin(f, moving, start_cu, [&](std::size_t a, std::size_t b, double d) {
      if (!member.empty() && !(member[a] && member[b])) return;
      nearest[a] = std::min(nearest[a], d), nearest[b] = std::min(nearest[b], d);
    });
    std::vector<double> of_moving;
    for (std::size_t i : moving) of_moving.push_back(nearest[i]);
    const auto middle = of_moving.begin() + std::ptrdiff_t(of_moving.size() / 2);
    std::nth_element(of_moving.begin(), middle, of_moving.end());
    if (std::isfinite(*middle)) return *middle;
  }
  return 0;
}

const char* PairKindName(int pair_kind) {
  static const char* const kNames[kPairKinds] = {
      "elastic-elastic", "elastic-liquid", "elastic-boundary", "liquid-liquid", "liquid-boundary"};
  return kNames[pair_kind];
}

double HeldPairs::LevelDistanceCu(int level) const {
  return cap_cu_ * std::exp2(-double(std::max(level, 0)) / kLevelsPerOctave);
}

ClosestPair HeldPairs::Observe(const FrameRef& f, const std::vector<std::size_t>& moving,
                               std::size_t pair_index) {
  const Trajectory& t = f.trajectory;
  particles_ = t.particle_count();
  ClosestPair closest{std::numeric_limits<double>::infinity()};
  ForEachPairWithin(f, moving, cap_cu_, [&](std::size_t a, std::size_t b, double d) {
    Update(a, b, d, PairKind(t.type[a], t.type[b]), pair_index);
    if (d < closest.distance_cu) closest = {d, a, b};
  });
  // A pair not within the cap at this frame has ended its runs.
  std::erase_if(streaks_, [&](const auto& entry) { return entry.second.last_pair != pair_index; });
  return closest;
}

void HeldPairs::Update(std::size_t first, std::size_t second, double distance_cu, int pair_kind,
                       std::size_t pair_index) {
  const std::uint64_t key = std::uint64_t(first) * particles_ + second;
  auto it = streaks_.try_emplace(key).first;
  Streak& s = it->second;  // new, or within the cap at the frame before (Observe erases others)
  s.last_pair = pair_index;
  // The deepest level whose distance is at least this pair's: levels are nested, so the pair is
  // within every level up to it and outside every level below it.
  const double octaves = distance_cu > 0 ? std::log2(cap_cu_ / distance_cu) : INFINITY;
  const int deepest = int(std::min<double>(std::floor(octaves * kLevelsPerOctave), kLevels - 1));
  for (int j = 0; j < kLevels; ++j) s.run[j] = j <= deepest ? s.run[j] + 1 : 0;
  Held& h = held_[pair_kind];
  for (int j = deepest; j > h.level; --j)
    if (s.run[j] >= hold_frames_) {
      h = {j, first, second, pair_index};
      break;
    }
}

}  // namespace owval::compare::internal
