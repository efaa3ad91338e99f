#include "held_pairs.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace owval::compare::internal {
namespace {

using Cell = std::array<std::int64_t, 3>;

struct Binned {
  Cell cell;
  std::size_t particle;
  bool operator<(const Binned& other) const { return cell < other.cell; }
};

Cell CellOf(const float* x, double cell_cu) {
  return {std::int64_t(std::floor(x[0] / cell_cu)), std::int64_t(std::floor(x[1] / cell_cu)),
          std::int64_t(std::floor(x[2] / cell_cu))};
}

bool Finite(const float* x) {
  return std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]);
}

// The finite particles within `radius_cu` of the moving particles' bounding box, sorted by cell
// (the walls' thousands far from them are never binned).
std::vector<Binned> BinNearMoving(const FrameRef& f, const std::vector<std::size_t>& moving,
                                  double radius_cu) {
  const Trajectory& t = f.trajectory;
  double low[3] = {INFINITY, INFINITY, INFINITY}, high[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (std::size_t i : moving) {
    const float* x = t.position(f.frame, i);
    if (!Finite(x)) continue;
    for (int a = 0; a < 3; ++a) low[a] = std::min(low[a], x[a] - radius_cu);
    for (int a = 0; a < 3; ++a) high[a] = std::max(high[a], x[a] + radius_cu);
  }
  std::vector<Binned> bins;
  for (std::size_t p = 0; p < t.particle_count(); ++p) {
    const float* x = t.position(f.frame, p);
    if (!Finite(x)) continue;
    bool near = true;
    for (int a = 0; a < 3; ++a) near = near && x[a] >= low[a] && x[a] <= high[a];
    if (near) bins.push_back({CellOf(x, radius_cu), p});
  }
  std::sort(bins.begin(), bins.end());
  return bins;
}

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

void ForEachPairWithin(const FrameRef& f, const std::vector<std::size_t>& moving, double radius_cu,
                       const std::function<void(std::size_t, std::size_t, double)>& visit) {
  if (!(radius_cu > 0)) return;
  const Trajectory& t = f.trajectory;
  const std::vector<Binned> bins = BinNearMoving(f, moving, radius_cu);
  const double radius_squared = radius_cu * radius_cu;
  for (std::size_t i : moving) {
    const float* x = t.position(f.frame, i);
    if (!Finite(x)) continue;
    const Cell c = CellOf(x, radius_cu);
    for (std::int64_t dx = -1; dx <= 1; ++dx)
      for (std::int64_t dy = -1; dy <= 1; ++dy)
        for (std::int64_t dz = -1; dz <= 1; ++dz) {
          const Binned key{{c[0] + dx, c[1] + dy, c[2] + dz}, 0};
          const auto [lo, hi] = std::equal_range(bins.begin(), bins.end(), key);
          for (auto it = lo; it != hi; ++it) {
            const std::size_t p = it->particle;
            // A pair of two moving particles is met from both: counted from the lower index.
            if (p == i || (p < i && KindOf(t.type[p]) != ParticleKind::kBoundary)) continue;
            const float* y = t.position(f.frame, p);
            const double ex = double(y[0]) - x[0], ey = double(y[1]) - x[1],
                         ez = double(y[2]) - x[2];
            const double squared = ex * ex + ey * ey + ez * ez;
            if (squared <= radius_squared)
              visit(std::min(i, p), std::max(i, p), std::sqrt(squared));
          }
        }
  }
}

double MedianNearestSpacing(const FrameRef& f, const std::vector<std::size_t>& moving,
                            double start_cu) {
  if (moving.empty()) return 0;
  const Trajectory& t = f.trajectory;
  std::vector<double> nearest(t.particle_count(), std::numeric_limits<double>::infinity());
  if (!(start_cu > 0)) start_cu = 1;
  // Once half the moving particles have a neighbour within the radius, the median is among them
  // (every other one's nearest lies farther). Forty doublings reach any finite box.
  for (int widen = 0; widen < 40; ++widen, start_cu *= 2) {
    ForEachPairWithin(f, moving, start_cu, [&](std::size_t a, std::size_t b, double d) {
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
  most_pairs_ = std::max(most_pairs_, streaks_.size());
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
