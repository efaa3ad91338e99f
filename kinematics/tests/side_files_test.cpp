// A worm run's side files (WCON, worm_motion_log.txt) against the trajectory they sit beside,
// on Sibernetic's 0.6 s worm run: its own files agree, edited copies do not.
#include "owval/kinematics/side_files.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include "owval/base/errors.hpp"
#include "owval/kinematics/midline.hpp"
#include "owval/kinematics/worm_track.hpp"
#include "owval/testing/scratch_directory.hpp"
#include "owval/trajectory/formats.hpp"
#include "owval/trajectory/frame_source.hpp"

namespace owval::kinematics {
namespace {
namespace fs = std::filesystem;

const fs::path kRun = fs::path(OWVAL_SHARED_DIR) / "reference/worm_alone_0.6s";

struct Worm {
  Trajectory trajectory;  // the run's particles
  WormTrack track;        // the WCON owval writes of the run
};

const Worm& Reference() {
  static const Worm worm = [] {
    TextReadOptions quiet;
    quiet.quiet = true;
    Trajectory t = ReadTrajectory(kRun / "position_buffer.txt.gz", quiet);
    WormTrack track = TrackFromTrajectory(t);
    return Worm{std::move(t), std::move(track)};
  }();
  return worm;
}

// The track against the run's particles, read frame by frame.
TrackAgreement CompareWithRun(const WormTrack& track) {
  const std::unique_ptr<FrameSource> run = MemoryFrameSource(Reference().trajectory);
  return CompareWithTrajectory(track, *run);
}

TEST(SideFiles, SiberneticsOwnMotionLogAndOwvalsWconDescribeTheRun) {
  if (!fs::exists(kRun)) GTEST_SKIP() << "no " << kRun;
  TextReadOptions quiet;
  quiet.quiet = true;
  // The run's 6-digit file read frame by frame, as the gates read a candidate.
  const std::unique_ptr<FrameSource> run = OpenFrameSource(kRun / "position_buffer.txt.gz", quiet);
  const fs::path dir = owval::testing::TestScratch("side_files_own");
  WriteWcon(Reference().track, dir / "worm.wcon");
  const TrackAgreement wcon = CompareWconWithTrajectory(dir / "worm.wcon", *run);
  EXPECT_TRUE(wcon.agrees) << wcon.detail;
  EXPECT_EQ(wcon.worst_fraction_of_allowance, 0);
  EXPECT_EQ(wcon.detail.rfind("200 time points; 0 disagree with the trajectory's skeleton and "
                              "centroid; worst 0 of its allowance",
                              0),
            0u)
      << wcon.detail;
  // Sibernetic's log is computed from full-precision floats, the trajectory from its 6-digit
  // prints: measured 0.113 of the allowance at worst.
  const TrackAgreement log =
      CompareWormMotionLogWithTrajectory(kRun / "worm_motion_log.txt.gz", *run);
  EXPECT_TRUE(log.agrees) << log.detail;
  EXPECT_GT(log.worst_fraction_of_allowance, 0.05);
  EXPECT_LT(log.worst_fraction_of_allowance, 0.2);
  // The whole log in memory gives the same comparison.
  EXPECT_EQ(CompareWithRun(ReadWormMotionLog(kRun / "worm_motion_log.txt.gz")).detail, log.detail);
  fs::remove_all(dir);
}

// WCON's cx, cy are the elastic particles' centroid: one from another run, or in µm labelled mm,
// was not compared and passed beside a skeleton that agrees.
TEST(SideFiles, AWconCentroidThatIsNotTheRunsDisagrees) {
  if (!fs::exists(kRun)) GTEST_SKIP() << "no " << kRun;
  const fs::path dir = owval::testing::TestScratch("side_files_centroid");
  const std::unique_ptr<FrameSource> run = MemoryFrameSource(Reference().trajectory);
  WormTrack t = Reference().track;
  for (double& cx : t.cx_mm) cx *= 1000;  // µm labelled mm, the skeleton right
  WriteWcon(t, dir / "worm.wcon");
  const TrackAgreement micrometres = CompareWconWithTrajectory(dir / "worm.wcon", *run);
  EXPECT_FALSE(micrometres.agrees);
  EXPECT_EQ(micrometres.detail.rfind("200 time points; 200 disagree with the trajectory's "
                                     "skeleton and centroid; worst ",
                                     0),
            0u)
      << micrometres.detail;
  EXPECT_NE(micrometres.detail.find(", centroid ("), std::string::npos) << micrometres.detail;
  EXPECT_EQ(micrometres.detail.find('\n'), std::string::npos);
  t = Reference().track;
  for (std::size_t i = 0; i < t.cx_mm.size(); ++i) {  // the centroid of frame 0, every frame
    t.cx_mm[i] = t.cx_mm[0];
    t.cy_mm[i] = t.cy_mm[0];
  }
  WriteWcon(t, dir / "worm.wcon");
  const TrackAgreement frozen = CompareWconWithTrajectory(dir / "worm.wcon", *run);
  EXPECT_FALSE(frozen.agrees) << frozen.detail;
  t = Reference().track;
  t.cy_mm[100] += 1e-4;  // 1e-4 mm (0.0135 cu), one frame
  EXPECT_FALSE(CompareWithRun(t).agrees);
  t.cy_mm[100] -= 1e-4;
  EXPECT_TRUE(CompareWithRun(t).agrees);
  t.cx_mm.clear();  // a WCON without a centroid: the skeleton alone
  t.cy_mm.clear();
  const TrackAgreement skeleton_only = CompareWithRun(t);
  EXPECT_TRUE(skeleton_only.agrees);
  EXPECT_NE(skeleton_only.detail.find("the trajectory's skeleton; worst"), std::string::npos)
      << skeleton_only.detail;
  fs::remove_all(dir);
}

TEST(SideFiles, EditedTracksDisagreeWithTheRun) {
  if (!fs::exists(kRun)) GTEST_SKIP() << "no " << kRun;
  WormTrack t = Reference().track;
  for (double& time_s : t.time_s) time_s *= 2;  // a frame rate claimed wrong
  EXPECT_EQ(CompareWithRun(t).detail,
            "time point 1 at t 0.006 s, the trajectory's frame at 0.003 s");
  t = Reference().track;
  for (auto& row : t.x_mm)
    for (float& x : row) x *= 1000;  // µm labelled mm
  EXPECT_FALSE(CompareWithRun(t).agrees);
  t = Reference().track;
  for (auto& row : t.y_mm)
    for (float& y : row) y = -y;  // mirrored left/right
  EXPECT_FALSE(CompareWithRun(t).agrees);
  t = Reference().track;
  for (std::size_t i = 0; i < t.x_mm.size(); ++i) {  // head and tail swapped
    std::reverse(t.x_mm[i].begin(), t.x_mm[i].end());
    std::reverse(t.y_mm[i].begin(), t.y_mm[i].end());
  }
  EXPECT_FALSE(CompareWithRun(t).agrees);
  t = Reference().track;
  for (std::size_t i = 1; i < t.x_mm.size(); ++i) {  // the worm of frame 0, every frame
    t.x_mm[i] = t.x_mm[0];
    t.y_mm[i] = t.y_mm[0];
  }
  const TrackAgreement frozen = CompareWithRun(t);
  EXPECT_FALSE(frozen.agrees);
  EXPECT_EQ(frozen.detail.rfind("200 time points; 199 disagree", 0), 0u) << frozen.detail;
  t = Reference().track;
  t.x_mm[100][40] += 1e-4f;  // 1e-4 mm (0.0135 cu), one point of one frame
  EXPECT_FALSE(CompareWithRun(t).agrees);
  t = Reference().track;
  t.time_s.pop_back();  // a frame missing
  t.x_mm.pop_back();
  t.y_mm.pop_back();
  t.cx_mm.pop_back();
  t.cy_mm.pop_back();
  EXPECT_EQ(CompareWithRun(t).detail, "199 time points, the trajectory 200 frames");
}

// A midline log line: t, then X:, Y:, Z: with 99 bin means each (Sibernetic's layout).
std::string LogLine(double t_s, double x_mm) {
  std::ostringstream line;
  line << t_s;
  for (const char* label : {"X:", "Y:", "Z:"}) {
    line << '\t' << label;
    for (int k = 0; k < kMidlineBins; ++k) line << '\t' << x_mm + 0.01 * k;
  }
  return line.str();
}

// The log as a hostile or careless writer leaves it: a blank line is skipped, and a cut line
// or a line that is not a log line is bad input naming its line (it was read as a frame with
// no bins, and the bins were then indexed).
TEST(SideFiles, MidlineLogReaderNamesTheLineItCannotRead) {
  const fs::path dir = owval::testing::TestScratch("midline_log");
  const auto read = [&](const std::string& text) {
    std::ofstream(dir / "worm_motion_log.txt") << text;
    return ReadWormMotionLog(dir / "worm_motion_log.txt");
  };
  const std::string first = LogLine(0, 0.1), second = LogLine(0.003, 0.2);
  const WormTrack track = read(first + "\n\n" + second + "\n");
  ASSERT_EQ(track.time_s.size(), 2u);
  EXPECT_EQ(track.x_mm[1].size(), std::size_t(kMidlineBins));
  EXPECT_FLOAT_EQ(track.x_mm[1][0], 0.2f);
  const auto error = [&](const std::string& text) {
    try {
      read(text);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string expected = "expected t, then X:, Y:, Z: each with 99 bin means (mm)";
  EXPECT_NE(
      error(first + "\n" + second.substr(0, second.size() / 2) + "\n").find(":2: " + expected),
      std::string::npos);
  EXPECT_NE(error(first + "\nnot a log line\n").find(":2: " + expected), std::string::npos);
  EXPECT_NE(error("X:\t1\n").find(":1: " + expected), std::string::npos);
  // A NUL byte is a byte of its line (gzgets' C string ended there: a line starting with one was
  // read as "" and indexed before its start).
  EXPECT_NE(error(first + "\n" + std::string(1, '\0') + "\n").find(":2: " + expected),
            std::string::npos);
  // A line with no end (a small gzip bomb's 64 MB of digits) is refused once it is longer than
  // any log line, not read whole into memory.
  EXPECT_NE(
      error(first + "\n" + std::string(std::size_t{3} << 20, '0')).find(":2: line longer than"),
      std::string::npos);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace owval::kinematics
