// The WCSPH scheme's parts: the Wendland C2 kernel against numerical integration and finite
// differences, δ-SPH's sign, XSPH on a uniform field, and the optimistic step's rollback.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include <random>

#include "kernels/simd.hpp"
#include "kernels/wendland_c2.hpp"
#include "owval/base/errors.hpp"
#include "owval/engine/constants.hpp"
#include "owval/engine/run.hpp"
#include "owval/engine/solver.hpp"
#include "wcsph/wcsph.hpp"

namespace owval::engine::internal {
namespace {

// ∫ W dV by the midpoint rule on an n³ grid over the support's cube [−2h, 2h]³.
double IntegrateWendland(double h, int n) {
  const WendlandC2<double> k = WendlandC2<double>::ForRadius(h);
  const double step = 4 * h / n;
  double sum = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int l = 0; l < n; ++l) {
        const double x = -2 * h + (i + 0.5) * step, y = -2 * h + (j + 0.5) * step,
                     z = -2 * h + (l + 0.5) * step;
        sum += k.W(std::sqrt(x * x + y * y + z * z));
      }
  return sum * step * step * step;
}

TEST(WendlandC2, IntegratesToOneOverItsSupport) {
  for (double h : {1.5e-5, 1.0, 3.0}) EXPECT_NEAR(IntegrateWendland(h, 120), 1.0, 2e-4) << h;
}

TEST(WendlandC2, GradientMatchesCentralDifferencesAndVanishesOutsideTheSupport) {
  const double h = 0.7;
  const WendlandC2<double> k = WendlandC2<double>::ForRadius(h);
  std::mt19937 random(17);
  std::uniform_real_distribution<double> u(-1.45, 1.45);
  const auto w = [&](double x, double y, double z) {
    return k.W(std::sqrt(x * x + y * y + z * z));
  };
  for (int trial = 0; trial < 200; ++trial) {
    const double x[3] = {u(random), u(random), u(random)};
    const double r = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    const double f = k.GradientOverR(r), e = 1e-6;
    for (int a = 0; a < 3; ++a) {
      double plus[3] = {x[0], x[1], x[2]}, minus[3] = {x[0], x[1], x[2]};
      plus[a] += e;
      minus[a] -= e;
      const double numeric =
          (w(plus[0], plus[1], plus[2]) - w(minus[0], minus[1], minus[2])) / (2 * e);
      EXPECT_NEAR(f * x[a], numeric, 1e-7 * (1 + std::abs(numeric))) << r;
    }
  }
  EXPECT_EQ(k.W(2 * h), 0.0);
  EXPECT_EQ(k.GradientOverR(2 * h + 1e-9), 0.0);
  EXPECT_NEAR(k.W(0), 21 / (16 * kPi * h * h * h), 1e-12);
  // dW/dr ≤ 0 everywhere inside the support: the kernel falls monotonically.
  for (double r = 0; r < 2 * h; r += 0.01) EXPECT_LE(k.GradientOverR(r), 0.0);
}

// A liquid block of n³ particles at spacing 1 cu (scale 1 mm/cu), optionally on a floor of
// three wall layers, in a box with room around it.
SiberneticConfig Block(int n, bool floor) {
  SiberneticConfig c;
  c.source = "wcsph test block";
  const int margin = 4;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        c.position.push_back(
            {float(margin + i + 0.5), float(margin + j + 0.5), float(margin + k + 0.5), 1.1f});
        c.velocity.push_back({0, 0, 0, 0});
      }
  if (floor)
    for (int i = 0; i < n + 2 * margin; ++i)
      for (int j = 1; j <= 3; ++j)
        for (int k = 0; k < n + 2 * margin; ++k) {
          c.position.push_back({float(i + 0.5), float(margin - j + 0.5), float(k + 0.5), 3.0f});
          c.velocity.push_back({0, 1, 0, 0});
        }
  const float size = float(n + 2 * margin);
  c.box = {0, size, 0, size + 8, 0, size};
  return c;
}

PhysicsConstants Millimetre(bool gravity) {
  PhysicsConstants k;
  k.simulation_scale = 1e-3;
  k.time_step_s = 1e-3;
  k.wcsph.min_sound_speed_m_s = 5;
  if (!gravity) k.gravity = {0, 0, 0};
  return k;
}

TEST(WcsphDensityDiffusion, VanishesForUniformDensityAndSmoothsABump) {
  const SiberneticConfig c = Block(7, false);
  PhysicsConstants k = Millimetre(false);
  k.wcsph.hydrostatic_start = 0;
  Wcsph solver(c, k, 1);
  EXPECT_NEAR(solver.spacing_m(), 1e-3, 1e-9);
  for (float rate : solver.DensityDiffusionRates()) EXPECT_EQ(rate, 0.0f);
  // A density bump on the centre particle (row 3·49 + 3·7 + 3 = 171).
  std::vector<float> density(c.particle_count(), 1000.0f);
  const std::size_t centre = 171;
  density[centre] = 1010.0f;
  solver.SetDensities(density);
  const std::vector<float> rates = solver.DensityDiffusionRates();
  EXPECT_LT(rates[centre], 0.0f);           // the bump flattens...
  EXPECT_GT(rates[centre + 1], 0.0f);       // ...into its neighbours
  EXPECT_GT(rates[centre + 7 + 49], 0.0f);  // diagonal neighbour too
  EXPECT_EQ(rates[0], 0.0f);                // outside the support: untouched
  // The pair term's own sign: denser i, dW/dr < 0 → negative.
  EXPECT_LT(DensityDiffusionPair(1010.0f, 1000.0f, -1.0f, 1e-9f), 0.0f);
}

TEST(WcsphXsph, LeavesAUniformVelocityFieldUnchanged) {
  const SiberneticConfig c = Block(6, false);
  Wcsph solver(c, Millimetre(false), 1);
  const Float4 v{0.3f, -0.2f, 0.125f, 0.0f};
  solver.SetVelocities(std::vector<Float4>(c.particle_count(), v));
  for (const Float4& u : solver.XsphVelocities()) {
    EXPECT_EQ(u.x, v.x);
    EXPECT_EQ(u.y, v.y);
    EXPECT_EQ(u.z, v.z);
  }
  // A sheared field is smoothed: the fastest particle slows down.
  std::vector<Float4> shear(c.particle_count(), Float4{});
  for (std::size_t i = 0; i < shear.size(); ++i) shear[i].x = float(c.position[i][1]) * 0.01f;
  shear[100].x = 1.0f;
  solver.SetVelocities(shear);
  EXPECT_LT(solver.XsphVelocities()[100].x, 1.0f);
}

bool SameBits(std::span<const Float4> a, std::span<const Float4> b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Float4)) == 0;
}

TEST(WcsphRollback, RestoreBringsBackTheStateBitForBit) {
  const SiberneticConfig c = Block(6, true);
  PhysicsConstants k = Millimetre(true);
  k.wcsph.optimistic_dt = 0;  // Step() would take its own checkpoints
  Wcsph solver(c, k, 1);
  for (int k = 0; k < 3; ++k) solver.Step();
  solver.Checkpoint();
  const std::vector<Float4> x(solver.positions().begin(), solver.positions().end());
  const std::vector<Float4> v(solver.velocities().begin(), solver.velocities().end());
  const std::vector<float> rho = solver.Density();
  for (int k = 0; k < 5; ++k) solver.Step();
  ASSERT_FALSE(SameBits(x, solver.positions()));
  solver.Restore();
  EXPECT_TRUE(SameBits(x, solver.positions()));
  EXPECT_TRUE(SameBits(v, solver.velocities()));
  EXPECT_EQ(std::memcmp(rho.data(), solver.Density().data(), rho.size() * sizeof(float)), 0);
}

TEST(WcsphRollback, RolledBackStepsRetakeTheSafeStepExactly) {
  // Every optimistic try rolls back (threshold ~0): the run must equal, bit for bit, the run
  // that steps dt_safe throughout, Morton reorders included.
  const SiberneticConfig c = Block(6, true);
  PhysicsConstants fixed = Millimetre(true), rolled = fixed;
  fixed.wcsph.optimistic_dt = 0;
  rolled.wcsph.rollback_threshold = 1e-12;
  rolled.wcsph.cooldown_steps = 2;
  fixed.wcsph.reorder_interval = rolled.wcsph.reorder_interval = 3;
  Wcsph a(c, fixed, 1), b(c, rolled, 1);
  for (int k = 0; k < 6; ++k) {
    a.Step();
    b.Step();
  }
  EXPECT_EQ(a.stats().rollbacks, 0u);
  EXPECT_GT(b.stats().rollbacks, 0u);
  EXPECT_EQ(a.stats().substeps, b.stats().substeps);
  EXPECT_TRUE(SameBits(a.positions(), b.positions()));
  EXPECT_TRUE(SameBits(a.velocities(), b.velocities()));
}

TEST(WcsphPairs, VectorAndScalarPathsGiveTheSameFloats) {
  // A splashing block (a dam break in miniature): lists of every length, walls, viscosity.
  SiberneticConfig c = Block(6, true);
  for (std::size_t i = 0; i < c.particle_count(); ++i)
    if (c.position[i][3] < 2) c.velocity[i] = {0.05f * float(i % 7), -0.1f, 0.02f, 0};
  PhysicsConstants k = Millimetre(true);
  k.wcsph.viscosity_alpha = 0.1;
  ForceScalarPaths(true);
  Wcsph scalar(c, k, 1);
  for (int step = 0; step < 4; ++step) scalar.Step();
  ForceScalarPaths(false);
  Wcsph vector(c, k, 1);
  for (int step = 0; step < 4; ++step) vector.Step();
  EXPECT_GT(scalar.stats().substeps, 4u);
  EXPECT_TRUE(SameBits(scalar.positions(), vector.positions()));
  EXPECT_TRUE(SameBits(scalar.velocities(), vector.velocities()));
}

TEST(WcsphRun, NamesItsTechniquesAndLogsItsSteps) {
  RunOptions o;
  o.backend = "wcsph";
  o.constants = Millimetre(true);
  o.duration_s = 0.005;
  o.log_step = 2;
  RunSummary summary;
  const Trajectory t = engine::Run(Block(5, true), o, &summary);
  EXPECT_EQ(t.provenance.at("producer"), "owval engine wcsph");
  const std::string& parameters = t.provenance.at("scheme_parameters");
  for (const char* name : {"Wendland C2", "density_diffusion = 1", "xsph = 1", "optimistic_dt = 1",
                           "morton_reorder = 1", "velocity Verlet"})
    EXPECT_NE(parameters.find(name), std::string::npos) << name;
  ASSERT_EQ(summary.frame_log.size(), t.frame_count());
  const nlohmann::json last = nlohmann::json::parse(summary.frame_log.back());
  EXPECT_NEAR(last["time_s"].get<double>(), t.time_s.back(), 1e-12);
  EXPECT_GT(last["substeps"].get<int>(), 0);
  EXPECT_LT(last["max_density_variation"].get<double>(), 0.03);
  SetConstant(&o.constants, "wcsph_xsph", 0);
  EXPECT_THROW(SetConstant(&o.constants, "wcsph_density_diffusion", 2), InputError);
}

TEST(WcsphRun, RefusesElasticParticles) {
  SiberneticConfig c = Block(3, false);
  c.position.insert(c.position.begin(), {5, 5, 5, 2.1f});
  c.velocity.insert(c.velocity.begin(), {0, 0, 0, 0});
  c.connection.assign(kConnectionSlots, {-1, 0, 0, 0});
  c.particle_mem_index.assign(kMembraneSlotsPerParticle, -1);
  RunOptions o;
  o.backend = "wcsph";
  o.constants = Millimetre(true);
  EXPECT_THROW(engine::Run(c, o), InputError);
}

TEST(WcsphRun, HugeForcesEndAsASimulationFailureInsteadOfNeverFinishing) {
  RunOptions o;
  o.backend = "wcsph";
  o.constants = Millimetre(true);
  o.constants.gravity = {0, 1e30, 0};  // the safe sub-step underflows: 10^19 sub-steps a step
  o.duration_s = 0.005;
  try {
    engine::Run(Block(5, true), o);
    FAIL() << "the run finished";
  } catch (const SimulationError& e) {
    EXPECT_NE(std::string(e.what()).find("adaptive time step fell to"), std::string::npos)
        << e.what();
  }
}

TEST(WcsphRun, AStopRequestedWithinALongStepEndsTheRunThere) {
  RunOptions o;
  o.backend = "wcsph";
  o.constants = Millimetre(true);
  o.constants.time_step_s = 0.1;  // thousands of sub-steps in each step
  o.duration_s = 1;
  int polls = 0;
  o.stop_requested = [&] { return ++polls > 20; };  // Run polls once a step, wcsph a sub-step
  RunSummary summary;
  engine::Run(Block(5, true), o, &summary);
  EXPECT_TRUE(summary.interrupted);
  EXPECT_FALSE(summary.checkpointed);
  EXPECT_LE(summary.steps, 2u);  // stopped within the first steps, not after 20 of them
}

}  // namespace
}  // namespace owval::engine::internal
