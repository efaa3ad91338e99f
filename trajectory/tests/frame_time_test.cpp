// Frame times must increase: frames are paired by time (PairFramesByTime), so a file whose times
// repeat or go back would pair a candidate's frames with the wrong reference frames. Every reader
// refuses it with one line naming the file, the frame and both times: HDF5's /time (read whole
// and frame by frame), Sibernetic text (its times derive from the header), WCON's t.
#include <gtest/gtest.h>
#include <unistd.h>
#include <zlib.h>

#include <filesystem>
#include <fstream>
#include <limits>

#include "owval/base/errors.hpp"
#include "owval/testing/scratch_directory.hpp"
#include "owval/testing/test_files.hpp"
#include "owval/trajectory/formats.hpp"
#include "owval/trajectory/frame_source.hpp"
#include "owval/trajectory/worm_formats.hpp"
#include "owval/trajectory/writer.hpp"
#include "read_errors.hpp"

namespace owval {
namespace {
namespace fs = std::filesystem;
using testing::ReadError;
using testing::ScratchFile;

// Three particles, one frame per time in `time_s`, written by owval's own HDF5 writer.
fs::path Hdf5WithTimes(const std::string& name, const std::vector<double>& time_s) {
  Trajectory t;
  t.box = {0, 10, 0, 10, 0, 10};
  t.time_step_s = 2e-5;
  t.log_step = 20;
  t.type = {2.1f, 1.1f, 3.0f};
  std::vector<float> x = {1, 2, 3, 4, 5, 6, 7, 8, 9};
  for (double time : time_s) {
    x[0] += 0.5f;
    t.AppendFrame(time, x.data());
  }
  const fs::path path = ScratchFile(name);
  WriteHdf5(t, path);
  return path;
}

std::string OpenError(const fs::path& path) {
  return testing::InputErrorOf([&] {
    const TextReadOptions quiet = testing::QuietReading();
    const auto source = OpenFrameSource(path, quiet);
    for (std::size_t f = 0; f < source->frame_count(); ++f) source->Frame(f);
  });
}

std::string Hdf5FrameReaderError(const fs::path& path) {
  return testing::InputErrorOf([&] { Hdf5FrameReader reader(path); });
}

TEST(FrameTimes, Hdf5WithADuplicatedTimeIsRefusedByEveryReader) {
  const fs::path path = Hdf5WithTimes("duplicated.h5", {0, 4e-4, 4e-4, 1.2e-3});
  const std::string expected = path.string() +
                               ": HDF5: /time: frame 2's time 4e-04 s is not after frame 1's "
                               "4e-04 s: frame times must increase";
  EXPECT_EQ(ReadError(path), expected);
  EXPECT_EQ(OpenError(path), expected);
  EXPECT_EQ(Hdf5FrameReaderError(path), expected);
}

TEST(FrameTimes, Hdf5WithReorderedFramesIsRefused) {
  const fs::path path = Hdf5WithTimes("reordered.h5", {0, 8e-4, 4e-4, 1.2e-3});
  const std::string expected = path.string() +
                               ": HDF5: /time: frame 2's time 4e-04 s is not after frame 1's "
                               "8e-04 s: frame times must increase";
  EXPECT_EQ(ReadError(path), expected);
  EXPECT_EQ(OpenError(path), expected);
}

// Times that differ in their last bit are told apart in the message.
TEST(FrameTimes, TheMessageShowsTimesExactly) {
  const double t1 = 0.1, t2 = std::nextafter(0.1, 0.0);
  const fs::path path = Hdf5WithTimes("last_bit.h5", {0, t1, t2});
  EXPECT_EQ(ReadError(path), path.string() +
                                 ": HDF5: /time: frame 2's time 0.09999999999999999 s is not "
                                 "after frame 1's 0.1 s: frame times must increase");
}

TEST(FrameTimes, IncreasingAndSingleFrameHdf5AreRead) {
  EXPECT_EQ(ReadError(Hdf5WithTimes("increasing.h5", {0, 4e-4, 8e-4})), "no error");
  EXPECT_EQ(OpenError(Hdf5WithTimes("one.h5", {0.5})), "no error");
}

// The text format has no time column: frame f's time is f x log step x time step. Only a time
// step and log step whose product overflows make a time that is not finite.
std::string OverflowingText() {
  return "0\n10\n0\n10\n0\n10\n0\n1\n0\n1e300\n2147483647\n"
         "1\t2\t3\t1.1\n1\t2\t3\t1.1\n1\t2\t3\t1.1\n";
}

TEST(FrameTimes, TextWhoseTimesOverflowIsRefusedPlainAndGzipped) {
  const fs::path plain = ScratchFile("overflow.txt");
  std::ofstream(plain) << OverflowingText();
  const std::string what =
      ": frame time = frame x log step x time step (header): frame 1's time inf s is not finite: "
      "frame times must be finite";
  EXPECT_EQ(ReadError(plain), plain.string() + what);
  EXPECT_EQ(OpenError(plain), plain.string() + what);
  const fs::path gz = ScratchFile("overflow.txt.gz");
  gzFile out = gzopen(gz.c_str(), "wb");
  const std::string text = OverflowingText();
  gzwrite(out, text.data(), unsigned(text.size()));
  gzclose(out);
  EXPECT_EQ(ReadError(gz), gz.string() + what);
  EXPECT_EQ(OpenError(gz), gz.string() + what);
}

// A valid run reads as before: frame f at exactly f x log step x time step.
TEST(FrameTimes, TextTimesAreStillFrameTimesLogStepTimesTimeStep) {
  const fs::path path = ScratchFile("valid.txt");
  std::ofstream(path) << "0\n10\n0\n10\n0\n10\n0\n1\n0\n2e-05\n20\n"
                         "1\t2\t3\t1.1\n1\t2\t4\t1.1\n1\t2\t5\t1.1\n";
  const Trajectory t = ReadTrajectory(path);
  ASSERT_EQ(t.frame_count(), 3u);
  for (std::size_t f = 0; f < 3; ++f) EXPECT_EQ(t.time_s[f], static_cast<double>(f) * 20 * 2e-5);
  const TextReadOptions quiet = testing::QuietReading();
  EXPECT_EQ(OpenFrameSource(path, quiet)->header().time_s, t.time_s);
}

fs::path WconWithTimes(const std::string& name, const std::string& t_unit,
                       const std::string& times) {
  const fs::path path = ScratchFile(name);
  std::ofstream(path) << R"({"units": {"t": ")" << t_unit
                      << R"(", "x": "mm", "y": "mm"}, "data": [{"id": "w", "t": [)" << times
                      << R"(], "x": [[0, 1], [0, 1], [0, 1]], "y": [[0, 0], [0, 0], [0, 0]]}]})";
  return path;
}

std::string WconError(const fs::path& path) {
  return testing::InputErrorOf([&] { ReadWcon(path); });
}

TEST(FrameTimes, WconTimesThatGoBackOrOverflowAreRefused) {
  const fs::path back = WconWithTimes("back.wcon", "s", "0, 2, 1");
  EXPECT_EQ(WconError(back), back.string() +
                                 ": data: t: frame 2's time 1 s is not after frame 1's 2 s: frame "
                                 "times must increase");
  // 1e308 hours is finite in the file and infinite in seconds.
  const fs::path huge = WconWithTimes("huge.wcon", "h", "0, 1, 1e308");
  EXPECT_EQ(WconError(huge), huge.string() +
                                 ": data: t: frame 2's time inf s is not finite: frame times "
                                 "must be finite");
  EXPECT_EQ(WconError(WconWithTimes("fine.wcon", "s", "0, 1, 2")), "no error");
}

TEST(FrameTimes, CheckNamesTheFirstBadFrame) {
  EXPECT_NO_THROW(CheckFrameTimesIncrease({}, "f"));
  EXPECT_NO_THROW(CheckFrameTimesIncrease({-1, 0, 3}, "f"));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  try {
    CheckFrameTimesIncrease({nan, 1}, "f", "w: ");
    FAIL() << "NaN accepted";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "f: w: frame 0's time nan s is not finite: frame times must be finite");
  }
}

}  // namespace
}  // namespace owval
