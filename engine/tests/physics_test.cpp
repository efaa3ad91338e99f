// The engine against hand-computed values and against Sibernetic's own runs.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>

#include "kernels/sph_constants.hpp"
#include "neighbours/neighbour_grid.hpp"
#include "neighbours/reciprocal_pairs.hpp"
#include "owval/base/errors.hpp"
#include "owval/compare/signal_metrics.hpp"
#include "owval/engine/run.hpp"
#include "owval/testing/test_files.hpp"
#include "owval/trajectory/formats.hpp"
#include "pcisph/pcisph.hpp"

namespace owval::engine {
namespace {
namespace fs = std::filesystem;
using internal::SphConstants;

TEST(Kernels, ConstantsMatchSiberneticsHostValuesToTheLastBit) {
  // The float values Sibernetic's host passes to its kernels (physics sheet §1); one ULP off in
  // m·Wpoly6 was enough to lose demo1 after a few hundred steps.
  const SphConstants k = SphConstants::From(PhysicsConstants{});
  EXPECT_EQ(k.mass_wpoly6, 9.10348116e+29f);
  EXPECT_EQ(k.mass_grad_wspiky, -1.25667754e+17f);
  EXPECT_EQ(k.mass_lap_wviscosity, 1.25667754e+17f);
  EXPECT_EQ(k.mass_wpoly6 * k.scale, 6.73657512e+24f);  // surfTensCoeff
  EXPECT_EQ(k.hs_m, 2.47159969e-05f);
  EXPECT_EQ(k.hs2_m2, 6.10880513e-10f);
  EXPECT_EQ(k.scale, 7.39999905e-06f);
  EXPECT_EQ(k.inverse_scale, 135135.156f);
  EXPECT_EQ(k.time_step_s, 1.99999995e-05f);
  EXPECT_EQ(k.cell_size_inverse, 0.149700597f);
  // Density floor = an isolated particle's density: m·Wpoly6·hS⁶ = 207.53 kg/m³.
  EXPECT_NEAR(k.mass_wpoly6 * k.hs6, 207.53, 0.01);
}

// n particles drawn uniformly in [lo, hi)³ (seeded); `type(i, x)` gives particle i's type code
// (Sibernetic's w: 1.x liquid, 2.x elastic, 3 boundary) and may move its x first (a wall);
// every non-boundary particle is moving.
template <class TypeOf>
internal::ParticleState RandomCloud(unsigned seed, std::size_t n, float lo, float hi, TypeOf type) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(lo, hi);
  internal::ParticleState s;
  s.Resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    float x = u(rng);
    const float w = type(i, &x);
    s.position[i] = {x, u(rng), u(rng), w};
    if (!internal::IsBoundary(w)) s.moving.push_back(std::int32_t(i));
  }
  return s;
}

TEST(Neighbours, SearchMatchesBruteForceWithinTheCap) {
  const std::size_t n = 400;
  internal::ParticleState s =
      RandomCloud(3, n, 1.0f, 29.0f, [](std::size_t i, float*) { return i % 2 ? 1.1f : 3.0f; });
  const SphConstants k = SphConstants::From(PhysicsConstants{});
  internal::NeighbourGrid grid({0, 30, 0, 30, 0, 30}, k);
  grid.SetStatic(s);
  grid.UpdateMoving(s);
  for (std::size_t i = 0; i < n; ++i) {
    internal::Neighbour slots[internal::kSlots];
    grid.FindNeighbours(s, std::int32_t(i), slots);
    std::vector<int> found, expected;
    for (const auto& slot : slots)
      if (slot.index >= 0) found.push_back(slot.index);
    for (std::size_t j = 0; j < n; ++j) {
      if (j == i) continue;
      const float dx = s.position[i].x - s.position[j].x, dy = s.position[i].y - s.position[j].y,
                  dz = s.position[i].z - s.position[j].z;
      if (dx * dx + dy * dy + dz * dz <= k.h2_cu) expected.push_back(int(j));
    }
    ASSERT_LE(expected.size(), 32u) << "the sparse test cloud stays under the 32 cap";
    std::sort(found.begin(), found.end());
    EXPECT_EQ(found, expected) << "particle " << i;
  }
}

TEST(Neighbours, ReciprocalPairsKeepExactlyThePairsListedBothWays) {
  // A cloud dense enough that most particles have more than 32 within h, so the capped lists
  // are one-sided; a wall of boundary particles on one side.
  internal::ParticleState s = RandomCloud(7, 700, 1.0f, 13.0f, [](std::size_t i, float* x) {
    if (i % 7 != 0) return i % 2 ? 1.1f : 2.1f;
    *x = *x * 0.1f + 0.5f;  // the wall: boundary particles at x in [0.6, 1.8)
    return 3.0f;
  });
  const SphConstants k = SphConstants::From(PhysicsConstants{});
  internal::NeighbourGrid grid({0, 30, 0, 30, 0, 30}, k);
  grid.SetStatic(s);
  grid.Refresh(&s, 1);
  const auto lists = [&](const internal::ParticleState& t, std::int32_t a, std::int32_t b) {
    const internal::Neighbour* slots = t.slots(std::size_t(a));
    for (int m = 0; m < internal::kSlots && slots[m].index >= 0; ++m)
      if (slots[m].index == b) return true;
    return false;
  };
  const internal::ParticleState before = s;
  std::size_t one_sided = 0;
  for (std::int32_t i : s.moving)
    for (int m = 0; m < internal::kSlots && before.slots(std::size_t(i))[m].index >= 0; ++m) {
      const std::int32_t j = before.slots(std::size_t(i))[m].index;
      if (!internal::IsBoundary(before.position[j].w) && !lists(before, j, i)) ++one_sided;
    }
  ASSERT_GT(one_sided, 100u) << "the cloud must overflow the 32-slot cap";
  EXPECT_EQ(internal::KeepReciprocalPairs(&s), one_sided);
  for (std::int32_t i : s.moving) {
    // What is kept: the old list in its order, less exactly the one-sided moving entries.
    std::vector<internal::Neighbour> expected;
    for (int m = 0; m < internal::kSlots && before.slots(std::size_t(i))[m].index >= 0; ++m) {
      const internal::Neighbour slot = before.slots(std::size_t(i))[m];
      if (internal::IsBoundary(before.position[slot.index].w) || lists(before, slot.index, i))
        expected.push_back(slot);
    }
    std::uint32_t boundary_bits = 0;
    for (std::size_t m = 0; m < internal::kSlots; ++m) {
      const internal::Neighbour got = s.slots(std::size_t(i))[m];
      if (m < expected.size()) {
        EXPECT_EQ(got.index, expected[m].index) << "particle " << i << " slot " << m;
        EXPECT_EQ(got.distance_m, expected[m].distance_m);
        if (internal::IsBoundary(s.position[got.index].w)) boundary_bits |= 1u << m;
      } else {
        EXPECT_EQ(got.index, -1) << "particle " << i << " slot " << m;
      }
    }
    EXPECT_EQ(s.boundary_slots[std::size_t(i)], boundary_bits) << "particle " << i;
    for (const internal::Neighbour* slot = s.slots(std::size_t(i));
         slot < s.slots(std::size_t(i)) + internal::kSlots && slot->index >= 0; ++slot) {
      if (!internal::IsBoundary(s.position[slot->index].w)) {
        EXPECT_TRUE(lists(s, slot->index, i)) << i << " lists " << slot->index << ", not back";
      }
    }
  }
}

SiberneticConfig SingleParticle(float y0) {
  SiberneticConfig c;
  c.source = "test";
  c.box = {0, 100, 0, 100, 0, 100};
  c.position = {{50, y0, 50, 1.1f}};
  c.velocity = {{0, 0, 0, 0}};
  return c;
}

TEST(Step, FreeFallMatchesSemiImplicitEulerExactly) {
  // y_n = y_0 − g·dt²·n(n+1)/2/s after n integrations; frame k holds k integrations.
  RunOptions o;
  o.duration_s = 200 * 2e-5;
  o.log_step = 1;
  const Trajectory t = engine::Run(SingleParticle(90), o);
  ASSERT_EQ(t.frame_count(), 200u);
  const double dt = 2e-5, s = 7.39999905e-06, g = 9.8;
  for (std::size_t n : {0u, 1u, 10u, 199u})
    EXPECT_NEAR(t.coordinate(n, 0, 1), 90 - g * dt * dt * double(n) * double(n + 1) / 2 / s, 2e-4)
        << n;
}

TEST(Step, AgarTouchingWormBodyIsRelabelled) {
  // Sibernetic's force kernel writes 2.32 into an agar particle's type when a worm-body particle
  // is within hS (sphFluid.cl:592-595); an agar particle with no worm-body neighbour keeps 2.3.
  SiberneticConfig c;
  c.source = "test";
  c.box = {0, 100, 0, 100, 0, 100};
  c.position = {{50, 50, 50, 2.3f}, {51.5f, 50, 50, 2.1f}, {20, 50, 50, 2.3f}};
  c.velocity.assign(3, {0, 0, 0, 0});
  c.connection.assign(3 * 32, {-1, 0, 0, 0});
  c.particle_mem_index.assign(3 * 7, -1);
  internal::Pcisph solver(c, PhysicsConstants{}, Integrator::kSemiImplicitEuler, 1);
  solver.Step();
  EXPECT_EQ(solver.state().position[0].w, 2.32f);
  EXPECT_EQ(solver.state().position[1].w, 2.1f);
  EXPECT_EQ(solver.state().position[2].w, 2.3f);
}

TEST(Step, LeapfrogFreeFallIsExactKinematics) {
  // Constant g: leapfrog gives y_n = y_0 − g·dt²·n²/2/s, Euler's n(n+1) differs by 0.05 cu at
  // n = 199.
  RunOptions o;
  o.duration_s = 200 * 2e-5;
  o.log_step = 1;
  o.integrator = Integrator::kLeapfrog;
  const Trajectory t = engine::Run(SingleParticle(90), o);
  ASSERT_EQ(t.frame_count(), 200u);
  const double dt = 2e-5, s = 7.39999905e-06, g = 9.8;
  for (std::size_t n : {0u, 1u, 10u, 199u})
    EXPECT_NEAR(t.coordinate(n, 0, 1), 90 - g * dt * dt * double(n) * double(n) / 2 / s, 2e-4) << n;
}

TEST(Step, NothingMovesAtStepZero) {
  RunOptions o;
  o.duration_s = 2e-5;
  const Trajectory t = engine::Run(SingleParticle(90), o);
  EXPECT_EQ(t.coordinate(0, 0, 1), 90.0f);
}

TEST(Run, RefusesParticleOutsideTheBox) {
  EXPECT_THROW(engine::Run(SingleParticle(150), {}), InputError);
}

TEST(Parity, OneSprigMatchesSibernetic) {
  if (!fs::exists(testing::kSharedDir / "reference")) GTEST_SKIP() << "no ../shared/reference";
  RunOptions o;
  o.duration_s = 0.05;
  o.log_step = 1;
  o.record_fields = false;
  const Trajectory t = engine::Run(
      ReadSiberneticConfig(testing::kSharedDir / "reference/one_sprig/configuration"), o);
  const auto m = compare::MeasureSignal(t.time_s, ParticleSeries(t, 0, 1));
  EXPECT_NEAR(*m.period_s, 0.7246e-3, 0.7246e-3 * 0.002);
  EXPECT_NEAR(*m.half_amplitude, 1.694, 1.694 * 0.005);
  EXPECT_NEAR(m.equilibrium, 18.352, 0.01);
  const Trajectory ref =
      ReadTrajectory(testing::kSharedDir / "reference/one_sprig/position_buffer.txt");
  ASSERT_EQ(ref.frame_count(), t.frame_count());
  for (std::size_t f = 0; f < ref.frame_count(); ++f)
    ASSERT_NEAR(t.coordinate(f, 0, 1), ref.coordinate(f, 0, 1), 2e-4) << "frame " << f;
}

// Frames where some moving particle's coordinate, printed as Sibernetic prints it (6 significant
// digits), differs from the reference's text; empty when the run reproduces it.
std::vector<std::string> PrintedDifferences(const Trajectory& run, const Trajectory& ref) {
  std::vector<std::string> differences;
  const std::size_t frames = std::min(run.frame_count(), ref.frame_count());
  char a[32], b[32];
  for (std::size_t f = 0; f < frames; ++f) {
    for (std::size_t p = 0; p < ref.particle_count(); ++p) {
      if (KindOf(ref.type[p]) == ParticleKind::kBoundary) continue;
      for (int axis = 0; axis < 3; ++axis) {
        std::snprintf(a, sizeof a, "%.6g", run.coordinate(f, p, axis));
        std::snprintf(b, sizeof b, "%.6g", ref.coordinate(f, p, axis));
        if (std::string(a) != b)
          differences.push_back("frame " + std::to_string(f) + " particle " + std::to_string(p) +
                                " axis " + std::to_string(axis) + ": " + a + " vs " + b);
      }
    }
  }
  return differences;
}

Trajectory RunReference(const std::string& name, double duration_s, int log_step) {
  RunOptions o;
  o.duration_s = duration_s;
  o.log_step = log_step;
  o.record_fields = false;
  return engine::Run(
      ReadSiberneticConfig(testing::kSharedDir / "reference" / name / "configuration"), o);
}

TEST(Parity, TestGravityReproducesSiberneticAtEveryPrintedDigit) {
  if (!fs::exists(testing::kSharedDir / "reference")) GTEST_SKIP() << "no ../shared/reference";
  // One liquid particle falls, hits the floor's wall particles (placed 0.167 cu outside the box)
  // and comes to rest: the Ihmsen wall correction, friction and the 4th normal component.
  const Trajectory t = RunReference("test_gravity", 0.05, 5);
  const Trajectory ref =
      ReadTrajectory(testing::kSharedDir / "reference/test_gravity/position_buffer.txt");
  ASSERT_EQ(t.frame_count(), ref.frame_count());
  const auto differences = PrintedDifferences(t, ref);
  EXPECT_TRUE(differences.empty()) << differences.size() << " differ, first " << differences[0];
}

TEST(Parity, TestEnergyLiquidBlockReproducesSiberneticWhileFalling) {
  if (!fs::exists(testing::kSharedDir / "reference")) GTEST_SKIP() << "no ../shared/reference";
  // 29,791 liquid particles, 32-neighbour truncation everywhere: frames 0-2 (300 steps).
  const Trajectory t = RunReference("test_energy", 0.006, 100);
  const Trajectory ref =
      ReadTrajectory(testing::kSharedDir / "reference/test_energy/position_buffer.txt.gz");
  ASSERT_EQ(t.frame_count(), 3u);
  const auto differences = PrintedDifferences(t, ref);
  EXPECT_TRUE(differences.empty()) << differences.size() << " differ, first " << differences[0];
}

TEST(Parity, Demo1ReproducesSiberneticAtEveryPrintedDigit) {
  if (!fs::exists(testing::kSharedDir / "reference")) GTEST_SKIP() << "no ../shared/reference";
  // Elastic cube, membranes and liquid over 10,000 steps: a one-ULP difference anywhere grows to
  // whole units within a few hundred steps (gotcha 20), so this holds only if every operation
  // is Sibernetic's.
  const Trajectory t = RunReference("demo1", 0.2, 20);
  const Trajectory ref =
      ReadTrajectory(testing::kSharedDir / "reference/demo1/position_buffer.txt");
  ASSERT_EQ(t.frame_count(), ref.frame_count());
  const auto differences = PrintedDifferences(t, ref);
  EXPECT_TRUE(differences.empty()) << differences.size() << " differ, first " << differences[0];
  // Issue 3's gates, stated on their own: centroid heights, extents, final position, finite.
  const auto elastic = GroupIndices(ref, "elastic");
  for (const char* group : {"elastic", "liquid"}) {
    const auto members = GroupIndices(ref, group);
    for (std::size_t f = 0; f < ref.frame_count(); ++f)
      ASSERT_NEAR(Centroid(t, f, members)[1], Centroid(ref, f, members)[1], 1.5)
          << group << " frame " << f;
  }
  for (std::size_t f : {0u, 122u, 244u, 488u}) {
    for (int a = 0; a < 3; ++a) {
      float lo_t = 1e9f, hi_t = -1e9f, lo_r = 1e9f, hi_r = -1e9f;
      for (std::size_t p : elastic) {
        lo_t = std::min(lo_t, t.coordinate(f, p, a)), hi_t = std::max(hi_t, t.coordinate(f, p, a));
        lo_r = std::min(lo_r, ref.coordinate(f, p, a)),
        hi_r = std::max(hi_r, ref.coordinate(f, p, a));
      }
      EXPECT_NEAR(hi_t - lo_t, hi_r - lo_r, 0.05 * (hi_r - lo_r)) << "frame " << f << " axis " << a;
    }
  }
  for (float x : t.positions) ASSERT_TRUE(std::isfinite(x));
  const std::size_t last = ref.frame_count() - 1;
  for (int axis : {0, 2})
    EXPECT_NEAR(Centroid(t, last, elastic)[axis], Centroid(ref, last, elastic)[axis], 8.9);
}

}  // namespace
}  // namespace owval::engine
