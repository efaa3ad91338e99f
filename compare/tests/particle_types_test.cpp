// The particle_types gate: every other gate reads the particles' kinds from the reference, so a
// candidate whose type codes are wrong (liquid written as elastic, sub-types dropped) passed with
// its positions right.
#include <gtest/gtest.h>

#include "owval/compare/parity.hpp"
#include "owval/testing/reference_runs.hpp"

namespace owval::compare {
namespace {

TEST(ParticleTypes, Demo1WithLiquidWrittenAsElasticFailsOnlyThere) {
  OWVAL_REQUIRE_DEMO1();
  const Trajectory& demo1 = *testing::SiberneticDemo1Run();
  Trajectory relabelled = demo1;
  std::size_t liquid = 0;
  for (float& type : relabelled.type)
    if (KindOf(type) == ParticleKind::kLiquid) type = 2.1f, ++liquid;
  ASSERT_EQ(liquid, 125u);
  const ParityReport r = CompareTrajectories(demo1, relabelled, {});
  EXPECT_EQ(r.FailedGates(), "particle_types");
  EXPECT_EQ(r.gate("particle_types")->value, 125.0);
  EXPECT_NE(r.gate("particle_types")
                ->detail.find("125 of 17841 differ; first particle 218: "
                              "candidate 2.1, reference 1.1"),
            std::string::npos)
      << r.gate("particle_types")->detail;
}

TEST(ParticleTypes, OneSprigWithItsElasticSubTypeDroppedFails) {
  // 2.1 written as 2: the elastic kernel's full stiffness needs 2.05 < type < 2.25.
  const Trajectory& one_sprig = testing::BundledOneSprigRun();
  Trajectory dropped = one_sprig;
  dropped.type[0] = 2.0f;
  const ParityReport r = CompareTrajectories(one_sprig, dropped, {});
  EXPECT_EQ(r.FailedGates(), "particle_types");
  EXPECT_EQ(CompareTrajectories(one_sprig, one_sprig, {}).gate("particle_types")->value, 0.0);
}

}  // namespace
}  // namespace owval::compare
