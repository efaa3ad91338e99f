// The closest_approach gate: two particles never coincide in an honest SPH or PBD run, so a
// candidate whose particles come much closer than the reference's ever do was edited. demo1 with
// a liquid particle on its neighbour's place from frame 1 on passed every gate before (its 4.2 cu
// is less than honest ports' own per-particle differences: docs/checklist.md).
#include <gtest/gtest.h>

#include <cmath>

#include "owval/compare/parity.hpp"
#include "owval/testing/reference_runs.hpp"

namespace owval::compare {
namespace {

// Particle p moved from frame 1 on to `fraction` of the way from particle q to where it was
// (0: on q's place).
Trajectory MovedTowards(const Trajectory& t, std::size_t p, std::size_t q, float fraction) {
  Trajectory out = t;
  for (std::size_t f = 1; f < out.frame_count(); ++f)
    for (int a = 0; a < 3; ++a)
      out.position(f, p)[a] =
          out.position(f, q)[a] + fraction * (out.position(f, p)[a] - out.position(f, q)[a]);
  return out;
}

TEST(ClosestApproach, ReferenceAgainstItselfMeasuresOne) {
  OWVAL_REQUIRE_DEMO1();
  const Trajectory& demo1 = *testing::SiberneticDemo1Run();
  const ParityReport r = CompareTrajectories(demo1, demo1, {});
  const Gate& g = *r.gate("closest_approach");
  EXPECT_EQ(g.value, 1.0);
  EXPECT_EQ(g.status, GateStatus::kPass);
  EXPECT_TRUE(r.pass()) << r.FailedGates();
}

TEST(ClosestApproach, Demo1WithALiquidParticleOnItsNeighboursPlaceFails) {
  OWVAL_REQUIRE_DEMO1();
  const Trajectory& demo1 = *testing::SiberneticDemo1Run();
  const ParityReport r = CompareTrajectories(demo1, MovedTowards(demo1, 300, 301, 0), {});
  EXPECT_EQ(r.FailedGates(), "closest_approach");  // liquid.worst_particle: 0.047 < 0.05
  const Gate& g = *r.gate("closest_approach");
  EXPECT_TRUE(std::isinf(g.value));
  EXPECT_NE(g.detail.find("candidate 0 cu (particles 300 liquid and 301 liquid"), std::string::npos)
      << g.detail;
}

TEST(ClosestApproach, Demo1WithALiquidParticleAThousandthOfTheWayFromItsNeighbourPasses) {
  OWVAL_REQUIRE_DEMO1();
  // The bound's stated limit: honest XPBD brings two liquid particles of demo1 within 6.3e-5 cu
  // (1/481 of the reference's closest approach), so a particle 1e-3 of its neighbour's distance
  // from it (about 1.7e-3 cu, 1/30 of the reference's) is not caught here.
  const Trajectory& demo1 = *testing::SiberneticDemo1Run();
  const ParityReport r = CompareTrajectories(demo1, MovedTowards(demo1, 300, 301, 1e-3f), {});
  const Gate& g = *r.gate("closest_approach");
  EXPECT_EQ(g.status, GateStatus::kPass) << g.value << ": " << g.detail;
  EXPECT_GT(g.value, 10.0);
}

}  // namespace
}  // namespace owval::compare
