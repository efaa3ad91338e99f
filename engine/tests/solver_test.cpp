// The solver interface: backends by name, the factory, and what Run does through it.
#include "owval/engine/solver.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <limits>
#include <string>

#include "owval/base/errors.hpp"
#include "owval/engine/muscles.hpp"
#include "owval/engine/run.hpp"
#include "owval/testing/scratch_directory.hpp"
#include "state/non_finite.hpp"

namespace owval::engine {
namespace {
namespace fs = std::filesystem;

SiberneticConfig TwoLiquidParticlesAt(float x1, float x2) {
  SiberneticConfig c;
  c.source = "two_particles";
  c.box = {0, 100, 0, 100, 0, 100};
  c.position = {{x1, 50, 50, 1.1f}, {x2, 50, 50, 1.1f}};
  c.velocity.assign(2, {0, 0, 0, 0});
  return c;
}

TEST(Backends, PcisphIsBuiltInAndOwvalIsItsAlias) {
  const auto known = KnownBackends();
  ASSERT_FALSE(known.empty());
  EXPECT_EQ(known[0], "pcisph");
  EXPECT_EQ(CanonicalBackend("pcisph"), "pcisph");
  EXPECT_EQ(CanonicalBackend("owval"), "pcisph");
}

TEST(Backends, UnknownNameIsInputErrorListingTheKnownOnes) {
  try {
    CanonicalBackend("metal");
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("unknown backend 'metal'"), std::string::npos) << what;
    for (const std::string& name : KnownBackends())
      EXPECT_NE(what.find(name), std::string::npos) << what;
  }
  RunOptions o;
  o.backend = "metal";
  EXPECT_THROW(MakeSolver(TwoLiquidParticlesAt(40, 60), o), InputError);
  EXPECT_THROW(engine::Run(TwoLiquidParticlesAt(40, 60), o), InputError);
}

// A thread count the machine cannot start is bad input, not a crash in the OpenMP runtime
// (100,000 threads segfaulted libgomp), for every backend.
// The one reading of an integrator's name (run requests, checkpoints, `pipeline --integrator`):
// a checkpoint naming another one ran semi-implicit Euler and said nothing.
TEST(Backends, IntegratorNamesAreEulerOrLeapfrogAndNothingElse) {
  EXPECT_EQ(ParseIntegrator("euler"), Integrator::kSemiImplicitEuler);
  EXPECT_EQ(ParseIntegrator("leapfrog"), Integrator::kLeapfrog);
  for (const std::string& bad :
       {std::string(), std::string("Leapfrog"), std::string("verlet"), std::string("euler\n")}) {
    try {
      ParseIntegrator(bad);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("expected euler or leapfrog"), std::string::npos);
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    }
  }
}

// The same for the muscle signal: a checkpoint naming another one ran `auto` and said nothing.
TEST(Backends, MuscleSignalNamesAreAutoOffOrWavesAndReadBack) {
  for (const MuscleSignal m :
       {MuscleSignal::kAuto, MuscleSignal::kOff, MuscleSignal::kSwimmingWaves})
    EXPECT_EQ(ParseMuscleSignal(MuscleSignalName(m)), m);
  EXPECT_EQ(ParseIntegrator(IntegratorName(Integrator::kLeapfrog)), Integrator::kLeapfrog);
  EXPECT_EQ(ParseIntegrator(IntegratorName(Integrator::kSemiImplicitEuler)),
            Integrator::kSemiImplicitEuler);
  for (const std::string& bad : {std::string(), std::string("Waves"), std::string("on")})
    EXPECT_THROW(ParseMuscleSignal(bad), InputError) << bad;
  EXPECT_TRUE(DrivesMuscles(MuscleSignal::kSwimmingWaves, "a/configuration"));
  EXPECT_TRUE(DrivesMuscles(MuscleSignal::kAuto, "worm_alone/configuration"));
  EXPECT_FALSE(DrivesMuscles(MuscleSignal::kAuto, "demo1/configuration"));
  EXPECT_FALSE(DrivesMuscles(MuscleSignal::kOff, "worm_alone/configuration"));
}

TEST(Solver, ThreadCountsOutsideZeroToTheMaximumAreInputErrors) {
  for (const std::string& backend : KnownBackends()) {
    RunOptions o;
    o.backend = backend;
    for (const int threads : {-1, kMaxThreads + 1, 100000}) {
      o.threads = threads;
      try {
        MakeSolver(TwoLiquidParticlesAt(40, 60), o);
        ADD_FAILURE() << backend << " took " << threads << " threads";
      } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("threads: expected 0 (every idle core) or 1 to 1024"),
                  std::string::npos)
            << e.what();
      }
    }
    o.threads = 3;  // more than this machine's cores is allowed
    EXPECT_EQ(MakeSolver(TwoLiquidParticlesAt(40, 60), o)->threads(), 3) << backend;
  }
}

TEST(Solver, FactoryBuildsAPcisphThatStepsAndExposesItsState) {
  RunOptions o;
  o.backend = "owval";
  const auto solver = MakeSolver(TwoLiquidParticlesAt(40, 60), o);
  EXPECT_EQ(solver->name(), "pcisph");
  EXPECT_TRUE(solver->reference_equivalent());
  ASSERT_EQ(solver->positions().size(), 2u);
  EXPECT_EQ(solver->positions()[1].x, 60.0f);
  solver->Step();
  solver->Step();
  EXPECT_EQ(solver->steps_done(), 2u);
  EXPECT_LT(solver->positions()[0].y, 50.0f);  // falling
  EXPECT_EQ(solver->Density().size(), 2u);
  EXPECT_EQ(solver->pressure().size(), 2u);
  EXPECT_EQ(solver->FirstNonFinite().particle, -1);
  o.integrator = Integrator::kLeapfrog;
  EXPECT_FALSE(MakeSolver(TwoLiquidParticlesAt(40, 60), o)->reference_equivalent());
}

// Only moving particles are checked, positions before velocities.
TEST(NonFinite, FindsTheFirstMovingPositionThenVelocity) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<Float4> x(3, Float4{1, 2, 3, 1}), v(3, Float4{0, 0, 0, 0});
  const std::vector<std::int32_t> moving = {0, 2};
  EXPECT_EQ(internal::FirstNonFiniteOf(x, v, moving).particle, -1);
  x[1].y = nan;  // not in the moving list: never changes, never checked
  EXPECT_EQ(internal::FirstNonFiniteOf(x, v, moving).particle, -1);
  v[0].z = nan;
  x[2].x = std::numeric_limits<float>::infinity();
  const Solver::NonFinite position = internal::FirstNonFiniteOf(x, v, moving);
  EXPECT_EQ(position.particle, 2);
  EXPECT_STREQ(position.quantity, "position");
  x[2].x = 0;
  const Solver::NonFinite velocity = internal::FirstNonFiniteOf(x, v, moving);
  EXPECT_EQ(velocity.particle, 0);
  EXPECT_STREQ(velocity.quantity, "velocity");
}

TEST(RunDump, NaNStateDumpGoesToTheDumpDirectory) {
  // Two particles at one point: the pressure term's direction is 0/0 at the first integration.
  const fs::path dir = owval::testing::TestScratch() / "dump";
  RunOptions o;
  o.duration_s = 10 * 2e-5;
  o.dump_dir = dir;
  try {
    engine::Run(TwoLiquidParticlesAt(50, 50), o);
    FAIL() << "no NaN";
  } catch (const SimulationError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("NaN at step 1"), std::string::npos) << what;
    EXPECT_NE(what.find("(position)"), std::string::npos) << what;
    EXPECT_NE(what.find(dir.string()), std::string::npos) << what;
  }
  EXPECT_TRUE(fs::exists(dir / "owval_nan_dump_step1.txt"));
  o.dump_dir.clear();
  try {
    engine::Run(TwoLiquidParticlesAt(50, 50), o);
    FAIL() << "no NaN";
  } catch (const SimulationError& e) {
    EXPECT_NE(std::string(e.what()).find("no state dump"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists("owval_nan_dump_step1.txt"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace owval::engine
