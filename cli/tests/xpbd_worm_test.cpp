// Issue 13's worm gates for the XPBD candidate: Sibernetic's muscle-driven worm
// (worm_alone_half_resolution) run 25 ms with `--backend xpbd` and compared by `owval compare`
// against Sibernetic's own OpenCL run of it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "cli_support.hpp"

namespace owval::testing {
namespace {

const std::filesystem::path kWorm =
    std::filesystem::path(OWVAL_SHARED_DIR) / "reference/worm_alone_0.6s";

nlohmann::json CompareJson(const std::string& args) {
  const Result r =
      Owval("compare " + (kWorm / "position_buffer.txt.gz").string() + " " + args + " --json");
  EXPECT_NE(r.exit_code, 2) << r.err;
  return nlohmann::json::parse(r.out);
}

TEST(XpbdWorm, DoesNotSinkAndKeepsItsCrossSectionOver25Ms) {
  if (ReferenceMissing(kWorm / "configuration")) GTEST_SKIP() << "needs " << kWorm;
  const auto out = Scratch() / "xpbd_worm";
  std::filesystem::remove_all(out);
  std::filesystem::create_directories(out);
  const Result run = Owval("run " + (kWorm / "configuration").string() +
                           " --backend xpbd --time 0.025 --log-step 150 --out " + out.string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string candidate = (out / "trajectory.h5").string();
  // Does not sink: the worm's (elastic) centroid y within 0.5 cu of the reference's every frame.
  const nlohmann::json y = CompareJson(candidate + " --group elastic --axis y");
  double worst = 0;
  for (const auto& f : y["frames"])
    worst = std::max(worst, std::abs(f["candidate_value_cu"].get<double>() -
                                     f["reference_value_cu"].get<double>()));
  EXPECT_EQ(y["frames"].size(), 9u);  // 0, 3, ..., 24 ms
  EXPECT_LT(worst, 0.5);
  // Keeps its cross-section: the mid-body diameter within 5% of the reference's at every frame.
  const nlohmann::json all = CompareJson(candidate);
  const nlohmann::json* cross_section = GateNamed(all, "worm.cross_section_diameter");
  ASSERT_NE(cross_section, nullptr) << all["gates"];
  EXPECT_EQ((*cross_section)["status"], "pass") << cross_section->dump();
  EXPECT_LT((*cross_section)["value"].get<double>(), 0.05);
  std::filesystem::remove_all(out);
}

}  // namespace
}  // namespace owval::testing
