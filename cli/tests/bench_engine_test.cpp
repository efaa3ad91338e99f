// owval bench engine --phases / --whole-run: where a run's time goes, per phase.
#include <gtest/gtest.h>

#include <algorithm>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_support.hpp"

namespace {
using owval::testing::Owval;

TEST(BenchEngine, PhasesReportEveryPhaseOfTheStepAndTheFrames) {
  const auto r = Owval("bench engine one_sprig --phases --steps 40 --log-step 10");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  const nlohmann::json& p = j.at("profile");
  EXPECT_EQ(p.at("steps"), 40);
  EXPECT_EQ(p.at("frames"), 4);  // steps 0, 10, 20, 30
  EXPECT_EQ(p.at("step_phases_s").size(), 10u);
  EXPECT_GT(p.at("step_phases_s").at("neighbours").get<double>(), 0);
  EXPECT_LE(p.at("step_s").get<double>(), p.at("wall_s").get<double>());
}

TEST(BenchEngine, XpbdReportsItsOwnPhases) {
  const auto r = Owval("bench engine one_sprig --backend xpbd --phases --steps 40 --log-step 10");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json p = nlohmann::json::parse(r.out).at("profile");
  const nlohmann::json& phases = p.at("step_phases_s");
  EXPECT_EQ(phases.size(), 7u);
  // one_sprig's bond needs its 28 substeps; the split scheme (the default) has no unsplit ones.
  EXPECT_GT(phases.at("bond_substeps").get<double>(), 0);
  EXPECT_EQ(phases.at("substeps").get<double>(), 0);
  EXPECT_LE(p.at("step_s").get<double>(), p.at("wall_s").get<double>());
}

TEST(BenchEngine, WholeRunNeedsAReferenceFolder) {
  // A configuration file, not a folder of ../shared/reference with its meta.json.
  const std::string config = std::string(OWVAL_SHARED_DIR) + "/reference/one_sprig/configuration";
  if (owval::testing::ReferenceMissing(config)) GTEST_SKIP() << "no " << config;
  const auto r = Owval("bench engine " + config + " --whole-run");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

// Without --phases the benchmark times one thread and every thread over --steps: its
// phase-profile flags were accepted and ignored (`--threads 1` timed both).
TEST(BenchEngine, ThePhaseProfilesFlagsNeedPhases) {
  for (const std::string flag : {"--threads", "--time", "--log-step"}) {
    const auto r = Owval("bench engine one_sprig --steps 1 " + flag + " 1");
    EXPECT_EQ(r.exit_code, 2) << flag << ": " << r.err;
    EXPECT_EQ(r.err, "owval: error: bench engine: " + flag +
                         " applies to --phases (or --whole-run); without it one thread and every "
                         "thread are timed over --steps\n");
    EXPECT_TRUE(r.out.empty()) << r.out;
  }
}

}  // namespace
