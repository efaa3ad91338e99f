// owval run on Sibernetic's worm (worm_alone_half_resolution, muscle-driven) writes
// worm_motion_log.txt equal to Sibernetic's own, byte for byte. A prefix of the 0.6 s reference
// keeps the test short (5 frames, 750 steps); the full run was checked once by hand (commit
// message / report).
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "../../trajectory/src/gzip.hpp"
#include "owval/base/atomic_output.hpp"
#include "owval/testing/scratch_directory.hpp"

namespace owval::kinematics {
namespace {
namespace fs = std::filesystem;

TEST(RunMidline, OwvalRunOfTheWormWritesSiberneticsMotionLogByteForByte) {
  const fs::path ref = fs::path(OWVAL_SHARED_DIR) / "reference/worm_alone_0.6s";
  const fs::path exe = fs::path(OWVAL_BINARY_DIR) / "owval";
  if (!fs::exists(ref) || !fs::exists(exe)) GTEST_SKIP() << "needs " << ref << " and " << exe;
  const fs::path out = owval::testing::TestScratch("run");
  const std::string command = exe.string() + " --quiet run " + (ref / "configuration").string() +
                              " --time 0.015 --log-step 150 --muscles waves --no-fields --out " +
                              out.string();
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  const std::string ours = ReadWholeFile(out / "worm_motion_log.txt");
  const std::string all = owval::internal::Gunzip(ReadWholeFile(ref / "worm_motion_log.txt.gz"),
                                                  "worm_motion_log.txt.gz");
  std::size_t end = 0;
  for (int line = 0; line < 5; ++line) end = all.find('\n', end) + 1;
  EXPECT_EQ(ours, all.substr(0, end));
  EXPECT_TRUE(fs::exists(out / "worm.wcon"));
  fs::remove_all(out);
}

std::string Output(const std::string& command) {
  std::string text;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return text;
  char buffer[4096];
  for (std::size_t n; (n = fread(buffer, 1, sizeof buffer, pipe)) > 0;) text.append(buffer, n);
  return pclose(pipe) == 0 ? text : "failed: " + command;
}

TEST(RunMidline, ConvertToWconThenKinematicsAgreesWithTheTrajectory) {
  const fs::path traj =
      fs::path(OWVAL_SHARED_DIR) / "reference/worm_alone_0.6s/position_buffer.txt.gz";
  const fs::path exe = fs::path(OWVAL_BINARY_DIR) / "owval";
  if (!fs::exists(traj) || !fs::exists(exe)) GTEST_SKIP() << "needs " << traj << " and " << exe;
  const fs::path wcon = owval::testing::TestScratch() / "converted.wcon";
  const std::string owval = exe.string() + " --quiet ";
  ASSERT_EQ(std::system((owval + "convert " + traj.string() + " " + wcon.string()).c_str()), 0);
  std::string from_wcon = Output(owval + "kinematics --json " + wcon.string());
  std::string from_traj = Output(owval + "kinematics --json " + traj.string());
  // Identical but for the "input" line.
  auto drop_input = [](std::string s) {
    const std::size_t at = s.find("\"input\"");
    return at == std::string::npos ? s : s.erase(at, s.find('\n', at) - at);
  };
  EXPECT_EQ(drop_input(from_wcon), drop_input(from_traj));
  EXPECT_NE(from_traj.find("\"wavelength_mm\""), std::string::npos) << from_traj;
  fs::remove(wcon);
}

}  // namespace
}  // namespace owval::kinematics
