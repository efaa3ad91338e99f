// The vector paths of the kernels (AVX-512, AVX2) give the scalar paths' floats, bit for bit, and
// the phase profile accounts for a run's steps.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <tuple>

#include "kernels/simd.hpp"
#include "owval/engine/profile.hpp"
#include "owval/engine/run.hpp"
#include "owval/testing/test_files.hpp"

namespace owval::engine {
namespace {
namespace fs = std::filesystem;

enum class Path { kCpuChoice, kScalar, kAvx2 };

Trajectory RunWith(Path path, const std::string& name, double duration_s, int threads = 1,
                   const std::string& backend = "pcisph", int xpbd_iterations = 1,
                   double xpbd_tensile_correction = 0) {
  internal::ForceScalarPaths(path == Path::kScalar);
  if (path == Path::kAvx2) internal::ForceAvx2Paths();
  RunOptions o;
  o.constants.xpbd.iterations = xpbd_iterations;
  o.constants.xpbd.tensile_correction = xpbd_tensile_correction;
  o.duration_s = duration_s;
  o.log_step = 10;
  o.threads = threads;
  o.backend = backend;
  const Trajectory t =
      Run(ReadSiberneticConfig(testing::kSharedDir / "reference" / name / "configuration"), o);
  internal::ForceScalarPaths(false);
  return t;
}

bool SameBits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

void ExpectSameBits(const std::string& name, double duration_s, Path vector_path,
                    const std::string& backend = "pcisph", int xpbd_iterations = 1,
                    double xpbd_tensile_correction = 0) {
  const Trajectory vector =
      RunWith(vector_path, name, duration_s, 1, backend, xpbd_iterations, xpbd_tensile_correction);
  const Trajectory scalar = RunWith(Path::kScalar, name, duration_s, 1, backend, xpbd_iterations,
                                    xpbd_tensile_correction);
  ASSERT_GT(vector.frame_count(), 1u);
  EXPECT_TRUE(SameBits(vector.positions, scalar.positions)) << name;
  EXPECT_TRUE(SameBits(vector.velocities, scalar.velocities)) << name;
  EXPECT_TRUE(SameBits(vector.density, scalar.density)) << name;
  EXPECT_TRUE(SameBits(vector.pressure, scalar.pressure)) << name;
}

// demo1: elastic matter, membranes and walls; test_energy: a dense block, where more than 32
// candidates lie within h and the farthest slot is replaced.
TEST(VectorPaths, GiveTheScalarPathsBitsOnDemo1) {
  ExpectSameBits("demo1", 0.004, Path::kCpuChoice);
}
TEST(VectorPaths, GiveTheScalarPathsBitsOnADenseLiquidBlock) {
  ExpectSameBits("test_energy", 0.0004, Path::kCpuChoice);
}
// The 8-lane paths, also on a CPU that would take the 16-lane ones. Every x86-64 CPU CI runs on
// has AVX2; on one without it there is no 8-lane path to check.
TEST(VectorPaths, EightLanePathsGiveTheScalarPathsBits) {
  const bool avx2 = internal::ForceAvx2Paths();
  internal::ForceScalarPaths(false);
  if (!avx2) return;
  ExpectSameBits("demo1", 0.004, Path::kAvx2);
  ExpectSameBits("test_energy", 0.0004, Path::kAvx2);
  ExpectSameBits("demo1", 0.004, Path::kAvx2, "xpbd");  // the bond pass and density lanes
  ExpectSameBits("test_energy", 0.0004, Path::kAvx2, "xpbd");
}

// XPBD's bond pass (bond_pushes.hpp) on demo1's 1,848 bonds, and its density projection in lanes
// (density_lanes.hpp) on demo1 and on a dense block (lists of 32, more than 4,096 movers).
TEST(VectorPaths, GiveTheScalarPathsBitsOnDemo1UnderXpbd) {
  ExpectSameBits("demo1", 0.004, Path::kCpuChoice, "xpbd");
}
// Two passes per substep: the second reads the λ the first left (each substep's solve starts at
// λ = 0 on both paths).
TEST(VectorPaths, GiveTheScalarPathsBitsOnDemo1UnderXpbdWithTwoPasses) {
  ExpectSameBits("demo1", 0.002, Path::kCpuChoice, "xpbd", 2);
}
TEST(VectorPaths, GiveTheScalarPathsBitsOnADenseLiquidBlockUnderXpbd) {
  ExpectSameBits("test_energy", 0.0004, Path::kCpuChoice, "xpbd");
}
// [MM13]'s s_corr (xpbd_tensile_correction) in the density lanes: the scalar loop's pair terms.
TEST(VectorPaths, GiveTheScalarPathsBitsUnderXpbdWithTheTensileCorrection) {
  ExpectSameBits("demo1", 0.004, Path::kCpuChoice, "xpbd", 1, 0.1);
  ExpectSameBits("test_energy", 0.0004, Path::kCpuChoice, "xpbd", 1, 0.1);
}

// The default thread count follows the machine's idle cores, so the output must not depend on it:
// each particle's arithmetic is done by one thread, in the same order, whatever the count.
// The worm under XPBD shares its bond substeps between the threads (its rows of bonds cut in two
// or three parts, xpbd.cpp's SharedBondSubsteps); demo1's bond substeps stay on one thread (too
// few rows to repay a barrier) and its corrections are forked (343 moving particles).
TEST(ThreadCount, GivesTheSameBitsOnOneThreadAsOnTwo) {
  for (const auto& [name, duration_s, backend, threads] : {std::tuple{"demo1", 0.004, "pcisph", 2},
                                                           {"test_energy", 0.0004, "pcisph", 2},
                                                           {"test_energy", 0.0004, "xpbd", 2},
                                                           {"demo1", 0.004, "xpbd", 2},
                                                           {"worm_alone_0.6s", 0.002, "xpbd", 2},
                                                           {"worm_alone_0.6s", 0.002, "xpbd", 3}}) {
    const Trajectory one = RunWith(Path::kCpuChoice, name, duration_s, 1, backend);
    const Trajectory more = RunWith(Path::kCpuChoice, name, duration_s, threads, backend);
    ASSERT_GT(one.frame_count(), 1u);
    const std::string run = std::string(name) + " " + backend + " on " + std::to_string(threads);
    EXPECT_TRUE(SameBits(one.positions, more.positions)) << run;
    EXPECT_TRUE(SameBits(one.velocities, more.velocities)) << run;
    EXPECT_TRUE(SameBits(one.density, more.density)) << run;
    EXPECT_TRUE(SameBits(one.pressure, more.pressure)) << run;
  }
}

TEST(PhaseProfile, CoversEveryStepAndFrame) {
  RunOptions o;
  o.duration_s = 0.001;  // 50 steps
  o.log_step = 20;
  o.threads = 1;
  const PhaseProfile p =
      ProfilePhases(ReadSiberneticConfig(testing::kSharedDir / "reference/demo1/configuration"), o);
  EXPECT_EQ(p.steps, 50u);
  EXPECT_EQ(p.frames, 3u);  // steps 0, 20, 40
  ASSERT_EQ(p.step.size(), 10u);
  double step_s = 0;
  for (const auto& t : p.step) {
    EXPECT_GT(t.seconds, 0) << t.phase;
    step_s += t.seconds;
  }
  EXPECT_LE(step_s + p.frame_s, p.wall_s * 1.0001);
}

}  // namespace
}  // namespace owval::engine
