// The AVX-512 paths of the kernels give the scalar paths' floats, bit for bit, and the phase
// profile accounts for a run's steps.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>

#include "kernels/simd.hpp"
#include "owval/engine/profile.hpp"
#include "owval/engine/run.hpp"

namespace owval::engine {
namespace {
namespace fs = std::filesystem;

const fs::path kShared = OWVAL_SHARED_DIR;

Trajectory RunWith(bool scalar, const std::string& name, double duration_s, int threads = 1) {
  internal::ForceScalarPaths(scalar);
  RunOptions o;
  o.duration_s = duration_s;
  o.log_step = 10;
  o.threads = threads;
  const Trajectory t = Run(ReadSiberneticConfig(kShared / "reference" / name / "configuration"), o);
  internal::ForceScalarPaths(false);
  return t;
}

bool SameBits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

void ExpectSameBits(const std::string& name, double duration_s) {
  const Trajectory vector = RunWith(false, name, duration_s);
  const Trajectory scalar = RunWith(true, name, duration_s);
  ASSERT_GT(vector.frame_count(), 1u);
  EXPECT_TRUE(SameBits(vector.positions, scalar.positions)) << name;
  EXPECT_TRUE(SameBits(vector.velocities, scalar.velocities)) << name;
  EXPECT_TRUE(SameBits(vector.density, scalar.density)) << name;
  EXPECT_TRUE(SameBits(vector.pressure, scalar.pressure)) << name;
}

// demo1: elastic matter, membranes and walls; test_energy: a dense block, where more than 32
// candidates lie within h and the farthest slot is replaced.
TEST(VectorPaths, GiveTheScalarPathsBitsOnDemo1) { ExpectSameBits("demo1", 0.004); }
TEST(VectorPaths, GiveTheScalarPathsBitsOnADenseLiquidBlock) {
  ExpectSameBits("test_energy", 0.0004);
}

// The default thread count follows the machine's idle cores, so the output must not depend on it:
// each particle's arithmetic is done by one thread, in the same order, whatever the count.
TEST(ThreadCount, GivesTheSameBitsOnOneThreadAsOnTwo) {
  for (const auto& [name, duration_s] : {std::pair{"demo1", 0.004}, {"test_energy", 0.0004}}) {
    const Trajectory one = RunWith(false, name, duration_s, 1);
    const Trajectory two = RunWith(false, name, duration_s, 2);
    ASSERT_GT(one.frame_count(), 1u);
    EXPECT_TRUE(SameBits(one.positions, two.positions)) << name;
    EXPECT_TRUE(SameBits(one.velocities, two.velocities)) << name;
    EXPECT_TRUE(SameBits(one.density, two.density)) << name;
    EXPECT_TRUE(SameBits(one.pressure, two.pressure)) << name;
  }
}

TEST(PhaseProfile, CoversEveryStepAndFrame) {
  RunOptions o;
  o.duration_s = 0.001;  // 50 steps
  o.log_step = 20;
  o.threads = 1;
  const PhaseProfile p =
      ProfilePhases(ReadSiberneticConfig(kShared / "reference/demo1/configuration"), o);
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
