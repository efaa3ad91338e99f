// Issue 16's long acceptance runs (ctest label "long"): owval run's peak memory does not grow with
// the run's length, and demo1 for 10 s at log step 20 (500,000 steps, 25,000 frames) completes
// within 150 MB with the stability gate applied to the stream. Minutes of work: run with
// `ctest -L long`; figures in docs/benchmarks.md.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <sstream>

#include "long_run_support.hpp"

namespace owval {
namespace {
using namespace owval::testing;

constexpr double kMemoryBoundMb = 150;

Finished RunDemo1(double time_s, const fs::path& out, std::vector<std::string> extra = {}) {
  std::vector<std::string> args = {
      "run", kDemo1.string(), "--time",    std::to_string(time_s), "--log-step",
      "20",  "--out",         out.string()};
  args.insert(args.end(), extra.begin(), extra.end());
  return RunOwval(args, out.string() + ".log");
}

TEST(LongRunMemory, Demo1PeakMemoryOfTwoSecondsIsWithinTenPercentOfPointTwo) {
  const Finished short_run = RunDemo1(0.2, ScratchDir("short"));
  const Finished long_run = RunDemo1(2.0, ScratchDir("long"));
  ASSERT_EQ(short_run.exit_code, 0);
  ASSERT_EQ(long_run.exit_code, 0);
  RecordProperty("peak_rss_mb_0_2s", std::to_string(short_run.peak_rss_mb));
  RecordProperty("peak_rss_mb_2s", std::to_string(long_run.peak_rss_mb));
  std::printf("demo1 0.2 s: %.1f MB peak, %.1f s; 2 s: %.1f MB peak, %.1f s\n",
              short_run.peak_rss_mb, short_run.wall_s, long_run.peak_rss_mb, long_run.wall_s);
  EXPECT_LT(std::abs(long_run.peak_rss_mb - short_run.peak_rss_mb) / short_run.peak_rss_mb, 0.10);
  EXPECT_LE(long_run.peak_rss_mb, kMemoryBoundMb);
}

// Checkpoints (solver state and pending HDF5 frames, megabytes each) must not pile up.
TEST(LongRunMemory, Demo1WithNineCheckpointsStaysWithinTheBound) {
  const Finished run = RunDemo1(0.5, ScratchDir("checkpoints"), {"--checkpoint-every", "2500"});
  ASSERT_EQ(run.exit_code, 0);
  std::printf("demo1 0.5 s, 9 checkpoints: %.1f MB peak\n", run.peak_rss_mb);
  EXPECT_LE(run.peak_rss_mb, kMemoryBoundMb);
}

TEST(LongRunMemory, Demo1TenSecondsCompletesWithinTheMemoryBoundAndReportsStability) {
  const fs::path out = ScratchDir("ten_seconds");
  const Finished run = RunDemo1(10.0, out, {"--stability", "--json"});
  const std::string log = Bytes(out.string() + ".log");
  std::printf("demo1 10 s: exit %d, %.1f MB peak, %.0f s wall\n", run.exit_code, run.peak_rss_mb,
              run.wall_s);
  // Exit 0: the gate passed; 1: it failed, and the JSON says which check and from which frame.
  ASSERT_TRUE(run.exit_code == 0 || run.exit_code == 1) << log;
  // The log holds stdout's JSON and stderr's lines (the failure line comes after the JSON when
  // the gate fails): read the one JSON value, whatever follows it.
  std::istringstream json_text(log.substr(log.find('{')));
  nlohmann::json result;
  json_text >> result;
  std::printf("stability: %s\n", result.at("stability").dump().c_str());
  EXPECT_EQ(result.at("steps"), 500000);
  EXPECT_EQ(result.at("frames"), 25000);
  EXPECT_EQ(result.at("stability").at("frames"), 25000);
  EXPECT_EQ(result.at("stability").at("pass").get<bool>(), run.exit_code == 0);
  EXPECT_LE(run.peak_rss_mb, kMemoryBoundMb);
  EXPECT_EQ(ReadHdf5(out / "trajectory.h5").frame_count(), 25000u);
  fs::remove_all(out);  // about 1 GB
}

}  // namespace
}  // namespace owval
