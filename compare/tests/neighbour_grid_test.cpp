// The pair gates' grid search (neighbour_grid.hpp) against a search of every pair: the same
// pairs, each once, at the same distances, whether the cells are packed into one sort key or
// sorted as they are (a particle far away), with particles on the cells' faces and at exactly
// the radius (where skipping a cell by its box must not lose a pair), and with a NaN particle.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <random>
#include <tuple>
#include <utility>
#include <vector>

#include "neighbour_grid.hpp"
#include "owval/testing/reference_runs.hpp"

namespace owval::compare {
namespace {

using Visit = std::tuple<std::size_t, std::size_t, double>;  // as the search reports it

bool Finite(const float* x) {
  return std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]);
}

// Every pair of finite particles within `radius_cu` with an end in `ends`, with
// `oriented(a, b)` (a < b) saying which end comes first, or that the pair is not reported.
template <typename Oriented>
std::vector<Visit> EveryPair(const FrameRef& f, const std::vector<std::size_t>& ends,
                             double radius_cu, const Oriented& oriented) {
  const Trajectory& t = f.trajectory;
  std::vector<char> is_end(t.particle_count(), 0);
  for (std::size_t p : ends) is_end[p] = 1;
  std::vector<Visit> out;
  for (std::size_t a : ends)
    for (std::size_t b = 0; b < t.particle_count(); ++b) {
      if (b == a || (is_end[b] && b < a)) continue;  // a pair of two ends once
      const float *x = t.position(f.frame, a), *y = t.position(f.frame, b);
      if (!Finite(x) || !Finite(y)) continue;
      const double ex = double(y[0]) - x[0], ey = double(y[1]) - x[1], ez = double(y[2]) - x[2];
      const double squared = ex * ex + ey * ey + ez * ez;
      if (squared > radius_cu * radius_cu) continue;
      if (const auto first_second = oriented(std::min(a, b), std::max(a, b)))
        out.emplace_back(first_second->first, first_second->second, std::sqrt(squared));
    }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<std::size_t> Moving(const Trajectory& t) {
  std::vector<std::size_t> moving;
  for (std::size_t p = 0; p < t.particle_count(); ++p)
    if (KindOf(t.type[p]) != ParticleKind::kBoundary) moving.push_back(p);
  return moving;
}

std::vector<std::size_t> Liquid(const Trajectory& t) {
  std::vector<std::size_t> liquid;
  for (std::size_t p = 0; p < t.particle_count(); ++p)
    if (KindOf(t.type[p]) == ParticleKind::kLiquid) liquid.push_back(p);
  return liquid;
}

// ForEachPairWithin from the non-boundary particles: every pair with one of them, lower first.
void ExpectPairsAsEveryPair(const FrameRef& f, double radius_cu) {
  const Trajectory& t = f.trajectory;
  const std::vector<std::size_t> moving = Moving(t);
  std::vector<Visit> found;
  internal::ForEachPairWithin(f, moving, radius_cu, [&](std::size_t a, std::size_t b, double d) {
    found.emplace_back(a, b, d);
  });
  std::sort(found.begin(), found.end());
  const auto boundary = [&](std::size_t p) { return KindOf(t.type[p]) == ParticleKind::kBoundary; };
  EXPECT_EQ(
      found,
      EveryPair(f, moving, radius_cu,
                [&](std::size_t a, std::size_t b) {
                  return boundary(a) && boundary(b) ? std::nullopt : std::optional{std::pair{a, b}};
                }))
      << "radius " << radius_cu << " cu, frame " << f.frame;
}

// ForEachNeighbourWithin from the liquid: every pair with a liquid particle, the liquid one first
// (the higher index when both are).
void ExpectNeighboursAsEveryPair(const FrameRef& f, double radius_cu) {
  const Trajectory& t = f.trajectory;
  const std::vector<std::size_t> liquid_particles = Liquid(t);
  std::vector<Visit> found;
  internal::ForEachNeighbourWithin(
      f, liquid_particles, radius_cu,
      [&](std::size_t a, std::size_t b, double d) { found.emplace_back(a, b, d); });
  std::sort(found.begin(), found.end());
  const auto liquid = [&](std::size_t p) { return KindOf(t.type[p]) == ParticleKind::kLiquid; };
  EXPECT_EQ(found, EveryPair(f, liquid_particles, radius_cu,
                             [&](std::size_t a, std::size_t b) {
                               if (liquid(b)) return std::optional{std::pair{b, a}};  // b > a
                               if (liquid(a)) return std::optional{std::pair{a, b}};
                               return std::optional<std::pair<std::size_t, std::size_t>>{};
                             }))
      << "radius " << radius_cu << " cu, frame " << f.frame;
}

TEST(NeighbourGrid, FindsEveryPairOfDemo1WithinTheGatesRadii) {
  OWVAL_REQUIRE_DEMO1();
  const Trajectory& demo1 = *testing::SiberneticDemo1Run();
  // Half and twice Sibernetic's r0 (1.67 cu): held_pair's cap and liquid_packing's support.
  for (std::size_t frame : {0, 120, 499})
    for (double radius_cu : {0.835, 3.34}) {
      ExpectPairsAsEveryPair({demo1, frame}, radius_cu);
      ExpectNeighboursAsEveryPair({demo1, frame}, radius_cu);
    }
}

// A lattice of `side`^3 particles `spacing` apart (float), liquid, elastic and boundary in turn.
Trajectory Lattice(int side, float spacing) {
  Trajectory t;
  std::vector<float> x;
  for (int i = 0; i < side; ++i)
    for (int j = 0; j < side; ++j)
      for (int k = 0; k < side; ++k) {
        x.insert(x.end(), {float(i) * spacing, float(j) * spacing, float(k) * spacing});
        t.type.push_back(std::array{1.1f, 2.1f, 3.1f}[std::size_t(i + j + k) % 3]);
      }
  t.AppendFrame(0, x.data());
  return t;
}

TEST(NeighbourGrid, FindsEveryPairWhenACellHoldsMoreThanOneBatch) {
  // Cells five spacings wide hold 125 particles, a column's three cells 375: more than the 64
  // candidates a batch takes (VisitBatch), so batches begin and end inside cells.
  const Trajectory t = Lattice(12, 0.25f);
  for (double radius_cu : {1.25, 1.1}) {
    ExpectPairsAsEveryPair({t, 0}, radius_cu);
    ExpectNeighboursAsEveryPair({t, 0}, radius_cu);
  }
}

TEST(NeighbourGrid, KeepsPairsAtExactlyTheRadiusOnTheCellsFaces) {
  // Neighbours a cell apart and on the cells' faces: the cell boxes' slack must not drop them.
  // 0.3 is not a float: some lattice pairs fall just inside the radius, some just outside.
  for (const float spacing : {1.0f, 0.3f, 0.7f}) {
    const Trajectory t = Lattice(9, spacing);
    for (double radius_cu : {double(spacing), 0.3, std::sqrt(2.0) * spacing, 2.0 * spacing}) {
      ExpectPairsAsEveryPair({t, 0}, radius_cu);
      ExpectNeighboursAsEveryPair({t, 0}, radius_cu);
    }
  }
}

TEST(NeighbourGrid, FindsTheSamePairsWithAParticleFarAwayAndOneNotFinite) {
  // 400 particles in a 12 cu cube, a liquid pair 1e8 cu away (the cells then span more than a
  // packed key holds: sorted as cells) and a NaN particle, which is never visited.
  std::mt19937 random(28);
  std::uniform_real_distribution<float> in_cube(0.0f, 12.0f);
  Trajectory t;
  std::vector<float> x;
  for (int p = 0; p < 400; ++p) {
    x.insert(x.end(), {in_cube(random), in_cube(random), in_cube(random)});
    t.type.push_back(std::array{1.1f, 2.1f, 3.1f}[std::size_t(p) % 3]);
  }
  x.insert(x.end(), {1e8f, 0, 0, 1e8f, 0.5f, 0, NAN, 1, 1});
  t.type.insert(t.type.end(), {1.1f, 1.1f, 1.1f});
  t.AppendFrame(0, x.data());
  for (double radius_cu : {0.5, 1.0, 2.5}) {
    ExpectPairsAsEveryPair({t, 0}, radius_cu);
    ExpectNeighboursAsEveryPair({t, 0}, radius_cu);
  }
  // Without the far pair: packed keys.
  t.positions.resize(400 * 3), t.type.resize(400);
  for (double radius_cu : {0.5, 1.0, 2.5}) {
    ExpectPairsAsEveryPair({t, 0}, radius_cu);
    ExpectNeighboursAsEveryPair({t, 0}, radius_cu);
  }
}

}  // namespace
}  // namespace owval::compare
