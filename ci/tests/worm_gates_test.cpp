// The worm's gates on Sibernetic's 0.6 s worm run, used as both reference and candidate.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>

#include "owval/ci/gates.hpp"
#include "owval/kinematics/worm_track.hpp"
#include "owval/testing/scratch_directory.hpp"
#include "owval/trajectory/formats.hpp"
#include "owval/trajectory/worm_formats.hpp"

namespace owval::ci {
namespace {
namespace fs = std::filesystem;

const fs::path kWorm =
    fs::path(OWVAL_SHARED_DIR) / "reference/worm_alone_0.6s/position_buffer.txt.gz";

fs::path WormDirectory() {
  const fs::path dir = owval::testing::TestScratch("worm");
  fs::create_symlink(kWorm, dir / "reference.txt.gz");
  fs::create_symlink(kWorm, dir / "candidate.txt.gz");
  return dir;
}

const GateResult* Find(const GateReport& r, const std::string& name) {
  for (const GateResult& g : r.gates)
    if (g.name == name) return &g;
  return nullptr;
}

TEST(WormGates, QuickTestRequiresAWconForWormRuns) {
  if (!fs::exists(kWorm)) GTEST_SKIP() << "no " << kWorm;
  const fs::path dir = WormDirectory();
  const GateReport without = QuickTest(dir);
  const GateResult* g = Find(without, "worm run wrote a WCON");
  ASSERT_TRUE(g);
  EXPECT_FALSE(g->pass);
  EXPECT_FALSE(without.pass());
  TextReadOptions quiet;
  quiet.quiet = true;
  WriteWcon(kinematics::TrackFromTrajectory(ReadTrajectory(kWorm, quiet)), dir / "worm.wcon");
  const GateReport with = QuickTest(dir);
  EXPECT_TRUE(with.pass()) << with.ToText();
  EXPECT_EQ(Find(with, "worm run wrote a WCON")->detail,
            "worm.wcon: 200 time points, 99 midline points");
  fs::remove_all(dir);
}

// The 0.6 s reference holds about one undulation: its bend angle crosses zero fewer than three
// times, so no frequency is accepted and the Tier-3 gate fails on it (an honest result, not a
// tolerance to loosen). The metrics and ranges are printed either way.
TEST(WormGates, ValidatePrintsEachTier3MetricWithItsBaselineRange) {
  if (!fs::exists(kWorm)) GTEST_SKIP() << "no " << kWorm;
  const fs::path dir = WormDirectory();
  const GateReport r = Validate(dir);
  std::printf("%s", r.ToText().c_str());
  for (const char* metric : {"speed", "frequency", "wavelength"}) {
    const GateResult* g = Find(r, std::string("Tier-3 ") + metric);
    ASSERT_TRUE(g) << metric;
    EXPECT_NE(g->detail.find("baseline (crawling)"), std::string::npos) << g->detail;
    EXPECT_TRUE(Find(r, std::string("kinematics parity ") + metric)->pass);
  }
  EXPECT_FALSE(Find(r, "Tier-3 frequency")->pass);
  EXPECT_NE(Find(r, "Tier-3 frequency")->detail.find("fewer than 3 zero crossings"),
            std::string::npos);
  EXPECT_FALSE(r.pass());
  fs::remove_all(dir);
}

}  // namespace
}  // namespace owval::ci
