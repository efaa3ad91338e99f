// The differentiable XPBD substrate (issue 14): backward kernels against finite differences,
// a deliberately broken backward caught, checkpointed reverse bit-identical to the full tape,
// and clipping/truncation options changing what they should.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "owval/base/errors.hpp"
#include "owval/engine/config.hpp"
#include "owval/engine/gradient.hpp"
#include "owval/testing/scratch_directory.hpp"
#include "xpbd/xpbd.hpp"

namespace owval::engine {
namespace {

const std::filesystem::path kDemo1 =
    std::filesystem::path(OWVAL_SHARED_DIR) / "reference/demo1/configuration";

class GradCheckKernel : public ::testing::TestWithParam<std::string> {};

TEST_P(GradCheckKernel, BackwardMatchesCentralDifferencesInDouble) {
  GradCheckOptions o;
  o.kernels = {GetParam()};
  o.directions = 2;
  const GradCheckSummary s = RunGradCheck(o);
  ASSERT_EQ(s.tests.size(), 4u);
  for (const GradCheckTest& t : s.tests) {
    EXPECT_LE(t.relative_error, 1e-4)
        << t.name << ": fd " << t.finite_difference << " analytic " << t.analytic;
    EXPECT_NE(t.analytic, 0.0) << t.name;  // a vanishing VJP would pass trivially
  }
  EXPECT_TRUE(s.pass);
}

INSTANTIATE_TEST_SUITE_P(Kernels, GradCheckKernel,
                         ::testing::Values("sph_density", "forces", "predict", "density_projection",
                                           "bond_projection", "bond_projection_jacobi", "box",
                                           "velocity", "velocity_correction", "step"));

class SabotagedKernel : public ::testing::TestWithParam<std::string> {};

TEST_P(SabotagedKernel, AFlippedSignInTheBackwardIsCaught) {
  GradCheckOptions o;
  o.kernels = {GetParam()};
  o.directions = 2;
  o.sabotage = GetParam();
  const GradCheckSummary s = RunGradCheck(o);
  EXPECT_FALSE(s.pass);
}

INSTANTIATE_TEST_SUITE_P(Kernels, SabotagedKernel,
                         ::testing::Values("forces", "density_projection", "bond_projection",
                                           "bond_projection_jacobi", "velocity_correction",
                                           "step"));

TEST(GradCheck, UnknownKernelIsBadInput) {
  GradCheckOptions o;
  o.kernels = {"pressure"};
  EXPECT_THROW(RunGradCheck(o), std::exception);
}

// The reverse pass's bookkeeping does not depend on the substep count: 4 instead of demo1's
// derived 55 keeps these tests short.
PhysicsConstants FourSubsteps() {
  PhysicsConstants k;
  k.xpbd.substeps = 4;
  return k;
}

// Demo1's elastic and liquid centroids every 10 steps against a fixed target.
std::vector<LossTerm> Demo1Loss(const SiberneticConfig& c, std::size_t steps) {
  std::vector<LossTerm> loss(2);
  for (std::size_t i = 0; i < c.particle_count(); ++i) {
    if (int(c.position[i][3]) == 2) loss[0].particles.push_back(std::int32_t(i));
    if (int(c.position[i][3]) == 1) loss[1].particles.push_back(std::int32_t(i));
  }
  for (LossTerm& t : loss) {
    t.target = LossTerm::Target::kCentroid;
    for (std::size_t s = 10; s <= steps; s += 10) {
      t.frame_steps.push_back(s);
      t.reference.push_back({Vec3d{40, 60, 40}});
    }
  }
  return loss;
}

bool SameBits(const GradientSummary& a, const GradientSummary& b) {
  return a.loss == b.loss && a.parameter_gradient == b.parameter_gradient &&
         a.position_gradient == b.position_gradient && a.velocity_gradient == b.velocity_gradient;
}

TEST(GradientReverse, CheckpointedEqualsFullTapeToTheLastBit) {
  const SiberneticConfig c = ReadSiberneticConfig(kDemo1);
  const DifferentiableXpbd model(c, FourSubsteps());
  const auto loss = Demo1Loss(c, 30);
  GradientOptions full;
  full.steps = 30;
  full.checkpoint_every = 0;
  const GradientSummary tape = model.Gradient(model.DefaultParameters(), loss, full);
  for (std::size_t k : {1, 7, 10}) {
    GradientOptions o = full;
    o.checkpoint_every = k;
    const GradientSummary g = model.Gradient(model.DefaultParameters(), loss, o);
    EXPECT_TRUE(SameBits(tape, g)) << "k = " << k;
    if (k > 1) {
      EXPECT_LT(g.peak_tape_bytes, tape.peak_tape_bytes / 2) << "k = " << k;
    }
  }
  double norm = 0;
  for (double v : tape.parameter_gradient) norm += std::abs(v);
  EXPECT_GT(norm, 0);
}

// A frame the run never reaches would be left out of the loss without a word: bad input, in the
// loss value and in the gradient alike.
TEST(GradientReverse, AFrameOutsideTheStepsIsBadInput) {
  const SiberneticConfig c = ReadSiberneticConfig(kDemo1);
  const DifferentiableXpbd model(c, FourSubsteps());
  const std::vector<LossTerm> loss = Demo1Loss(c, 20);
  GradientOptions o;
  o.steps = 10;
  EXPECT_THROW(model.Gradient(model.DefaultParameters(), loss, o), InputError);
  EXPECT_THROW(model.Loss(model.DefaultParameters(), loss, 10), InputError);
  std::vector<LossTerm> at_zero = Demo1Loss(c, 10);
  at_zero[0].frame_steps[0] = 0;
  EXPECT_THROW(model.Loss(model.DefaultParameters(), at_zero, 10), InputError);
  EXPECT_NO_THROW(model.Loss(model.DefaultParameters(), Demo1Loss(c, 10), 10));
}

TEST(GradientReverse, ClippingAndTruncationChangeOnlyWhatTheyShould) {
  const SiberneticConfig c = ReadSiberneticConfig(kDemo1);
  const DifferentiableXpbd model(c, FourSubsteps());
  const auto loss = Demo1Loss(c, 30);
  GradientOptions o;
  o.steps = 30;
  const GradientSummary plain = model.Gradient(model.DefaultParameters(), loss, o);
  // A window as long as the run and a norm no step reaches change nothing.
  GradientOptions wide = o;
  wide.window = 30;
  wide.clip_norm = 1e300;
  const GradientSummary same = model.Gradient(model.DefaultParameters(), loss, wide);
  EXPECT_TRUE(SameBits(plain, same));
  EXPECT_EQ(same.clipped_steps, 0u);
  // Truncation: the loss is the same, the initial state sees only the first window's frames
  // (frame 10), the parameters every window's.
  GradientOptions cut = o;
  cut.window = 10;
  const GradientSummary truncated = model.Gradient(model.DefaultParameters(), loss, cut);
  EXPECT_EQ(truncated.loss, plain.loss);
  EXPECT_NE(truncated.position_gradient, plain.position_gradient);
  GradientOptions first = o;
  first.steps = 10;
  const GradientSummary ten = model.Gradient(model.DefaultParameters(), Demo1Loss(c, 10), first);
  EXPECT_EQ(truncated.position_gradient, ten.position_gradient);
  EXPECT_NE(truncated.parameter_gradient, ten.parameter_gradient);
  // Clipping: every step's state cotangent at most the clip norm.
  GradientOptions clip = o;
  clip.clip_norm = 1e-6;
  const GradientSummary clipped = model.Gradient(model.DefaultParameters(), loss, clip);
  EXPECT_EQ(clipped.loss, plain.loss);
  EXPECT_GT(clipped.clipped_steps, 0u);
  double norm = 0;
  for (const Vec3d& g : clipped.position_gradient)
    for (double v : g) norm += v * v;
  for (const Vec3d& g : clipped.velocity_gradient)
    for (double v : g) norm += v * v;
  EXPECT_LE(std::sqrt(norm), 1e-6 * (1 + 1e-12));
}

// demo1 with the unsplit step (xpbd_density_passes = 0), where its loss is well conditioned. With
// the default split step, demo1's central differences scatter by 2-5% (GradCheckOptions): the
// split step's 100-step check is test_energy's, below.
TEST(GradientReverse, HundredStepDemo1GradientOfTheUnsplitStepMatchesFiniteDifferences) {
  GradCheckOptions o;
  o.kernels = {"reverse"};
  o.directions = 1;
  o.end_to_end_config = kDemo1.string();
  o.end_to_end_density_passes = 0;
  const GradCheckSummary s = RunGradCheck(o);
  ASSERT_EQ(s.tests.size(), 2u);
  for (const GradCheckTest& t : s.tests)
    EXPECT_LE(t.relative_error, 1e-3)
        << t.name << ": fd " << t.finite_difference << " analytic " << t.analytic;
}

// The default split step (bonds on substeps, one density and wall correction per step) over 40
// steps of Sibernetic's liquid block with its walls (100 steps agree to 2.8e-4 as well, in 64 s).
TEST(GradientReverse, FortyStepTestEnergyGradientOfTheSplitStepMatchesFiniteDifferences) {
  GradCheckOptions o;
  o.kernels = {"reverse"};
  o.directions = 1;
  o.end_to_end_steps = 40;
  o.end_to_end_config =
      (std::filesystem::path(OWVAL_SHARED_DIR) / "reference/test_energy/configuration").string();
  const GradCheckSummary s = RunGradCheck(o);
  ASSERT_EQ(s.tests.size(), 2u);
  for (const GradCheckTest& t : s.tests) {
    EXPECT_NE(t.name.find("density_passes=1"), std::string::npos) << t.name;
    EXPECT_LE(t.relative_error, 1e-3)
        << t.name << ": fd " << t.finite_difference << " analytic " << t.analytic;
  }
}

// One liquid particle falling in an empty box: no parameter but gravity and the floor moves it,
// so the self-referenced loss (the model against itself at shifted parameters) sits at its
// minimum with an exactly zero gradient, against difference quotients of rounding noise (2e-13).
// Their ratio was 1, and free_fall's pipeline failed its gradient check on a right gradient.
// A zero is compared absolutely, as Ceres' GradientChecker does; a wrong nonzero one still fails.
TEST(GradientReverse, AZeroGradientAtTheLossMinimumIsComparedAbsolutely) {
  const std::filesystem::path config = owval::testing::TestScratch() / "fall.cfg";
  {
    std::ofstream out(config);
    out << "[simulation box]\n0\n33.4\n0\n33.4\n0\n33.4\n[position]\n16.7\t20\t16.7\t1.1\n"
           "[velocity]\n0\t0\t0\t1.1\n[connection]\n[membranes]\n[particleMemIndex]\n[end]\n";
  }
  GradCheckOptions o;
  o.kernels = {"reverse"};
  o.directions = 2;
  o.end_to_end_config = config.string();
  const GradCheckSummary s = RunGradCheck(o);
  std::filesystem::remove(config);
  ASSERT_EQ(s.tests.size(), 4u);
  for (const GradCheckTest& t : s.tests) {
    EXPECT_EQ(t.analytic, 0) << t.name;
    EXPECT_LT(std::abs(t.finite_difference), 1e-9) << t.name;
    EXPECT_TRUE(t.pass) << t.name << ": relative error " << t.relative_error;
  }
}

}  // namespace
}  // namespace owval::engine

namespace owval::engine {
namespace {

// Where neither the wall correction nor membranes act (one_sprig's particle hangs far from the
// walls), the differentiable model is the run's XPBD step: the double solver's trajectory, one
// step later (a run's first step moves nothing).
TEST(DifferentiableModel, ReproducesTheDoubleXpbdRunOnOneSprig) {
  const SiberneticConfig c = ReadSiberneticConfig(std::filesystem::path(OWVAL_SHARED_DIR) /
                                                  "reference/one_sprig/configuration");
  const DifferentiableXpbd model(c, PhysicsConstants{});  // both with the derived 28 substeps
  const auto frames = model.Trajectory(model.DefaultParameters(), 200);
  internal::Xpbd<double> run(c, PhysicsConstants{}, 1);
  run.Step();
  double worst = 0;
  for (std::size_t t = 0; t < frames.size(); ++t) {
    run.Step();
    for (int a = 0; a < 3; ++a)
      worst = std::max(worst, std::abs(run.exact_positions()[0][a] - frames[t][0][a]));
  }
  EXPECT_LT(worst, 1e-9);
  EXPECT_GT(std::abs(frames.back()[0][1] - frames.front()[0][1]), 0.5);  // it does oscillate
}

}  // namespace
}  // namespace owval::engine

namespace owval::engine {
namespace {

// An elastic cluster in the middle of an empty box (no walls, no liquid, 14 cu from every face),
// every particle bonded to the seven others and stretched 5%: the split step's Jacobi bond passes,
// which the differentiable model follows. The pair forces are off (the run evaluates them in
// float). The compressed cluster is chaotic: the two differ by 1.8e-9 cu after one step (the
// run holds its acceleration in float) and that grows ~28% a step, so four steps are compared;
// a Gauss-Seidel bond pass (the unsplit step's) is 2.5e-6 cu off after one.
TEST(DifferentiableModel, ReproducesTheDoubleXpbdSplitStepOfABondedCluster) {
  SiberneticConfig c;
  c.source = "bonded cluster";
  c.box = {0, 40, 0, 40, 0, 40};
  const float jitter[8] = {0.1f, -0.2f, 0.05f, 0.15f, -0.1f, 0.2f, -0.05f, 0.0f};
  for (int i = 0; i < 8; ++i) {
    c.position.push_back({18.0f + 1.6f * float(i & 1) + jitter[i],
                          18.0f + 1.6f * float((i >> 1) & 1),
                          18.0f + 1.6f * float(i >> 2) - jitter[7 - i], 2.1f});
    c.velocity.push_back({0.01f * float(i), 0, -0.01f * float(i), 0});
  }
  c.connection.assign(8 * kConnectionSlots, {-1, 0, 0, 0});
  for (int a = 0; a < 8; ++a) {
    int slot = 0;
    for (int b = 0; b < 8; ++b) {
      if (a == b) continue;
      const Row4 &pa = c.position[a], &pb = c.position[b];
      const double d = std::hypot(pa[0] - pb[0], pa[1] - pb[1], pa[2] - pb[2]);
      c.connection[a * kConnectionSlots + slot++] = {float(b), float(0.95 * d), 0, 0};
    }
  }
  c.particle_mem_index.assign(8 * kMembraneSlotsPerParticle, -1);
  PhysicsConstants constants;
  constants.xpbd.viscosity = 0, constants.xpbd.surface_tension = 0;
  ASSERT_EQ(constants.xpbd.density_passes, 1);  // the default split step
  const DifferentiableXpbd model(c, constants);
  const auto frames = model.Trajectory(model.DefaultParameters(), 4);
  internal::Xpbd<double> run(c, constants, 1);
  run.Step();
  double worst = 0, moved = 0;
  for (std::size_t t = 0; t < frames.size(); ++t) {
    run.Step();
    for (std::size_t i = 0; i < c.position.size(); ++i)
      for (int a = 0; a < 3; ++a) {
        worst = std::max(worst, std::abs(run.exact_positions()[i][a] - frames[t][i][a]));
        moved = std::max(moved, std::abs(frames[t][i][a] - frames[0][i][a]));
      }
  }
  EXPECT_LT(worst, 1e-7);
  EXPECT_GT(moved, 1e-3);  // the stretched bonds pull the cluster together
}

}  // namespace
}  // namespace owval::engine
