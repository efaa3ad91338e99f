// Sibernetic's muscles_activity_buffer.txt: the reader refuses what is not 96 finite values a
// line (naming file and line), reads plain and gzip files alike, and the comparison with a signal
// fails a value moved past the print's rounding, a line shifted, or a line missing. The signal
// here is a made-up one (kinematics does not link the engine); ci's worm gate tests hold
// Sibernetic's own file to owval's MuscleSimulationSignal.
#include "owval/kinematics/muscle_log.hpp"

#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>

#include "owval/base/errors.hpp"
#include "owval/testing/scratch_directory.hpp"

namespace owval::kinematics {
namespace {
namespace fs = std::filesystem;

// Activations that change with the step and the muscle, over four decades, and zeros.
MuscleActivations MadeUp(double step) {
  MuscleActivations a{};
  for (std::size_t m = 0; m < kLoggedMuscles; ++m)
    a[m] = m % 5 == 0 ? 0.0f
                      : float((0.5 + 0.45 * std::sin(0.01 * step + 0.3 * double(m))) *
                              std::pow(10.0, -double(m % 4)));
  return a;
}

// A worm-free trajectory header of `frames` frames, `log_step` steps apart at 2e-5 s.
Trajectory Header(std::size_t frames, int log_step) {
  Trajectory t;
  t.time_step_s = 2e-5;
  t.log_step = log_step;
  for (std::size_t f = 0; f < frames; ++f) t.time_s.push_back(double(f * log_step) * 2e-5);
  return t;
}

std::string Lines(std::size_t frames, int log_step) {
  std::string text;
  for (std::size_t f = 0; f < frames; ++f)
    text += FormatMuscleLogLine(MadeUp(double(f) * log_step));
  return text;
}

fs::path Write(const std::string& name, const std::string& text) {
  const fs::path path = owval::testing::TestScratch() / name;
  std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
  return path;
}

std::string ErrorOf(const fs::path& path) {
  try {
    MuscleLogReader reader(path);
    PrintedActivations values{};
    while (reader.Next(&values)) {
    }
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(MuscleLog, ALineIsNinetySixValuesPrintedPercentE) {
  MuscleActivations a{};
  a[0] = 0.0061088884f;
  a[95] = 0.5749999f;
  const std::string line = FormatMuscleLogLine(a);
  EXPECT_EQ(line.substr(0, 26), "6.108888e-03\t0.000000e+00\t");
  EXPECT_EQ(line.substr(line.size() - 14), "\t5.749999e-01\n");
  EXPECT_EQ(std::count(line.begin(), line.end(), '\t'), 95);
}

TEST(MuscleLog, ReadsPlainAndGzipFilesLineByLine) {
  const std::string text = Lines(3, 150);
  const fs::path plain = Write("muscles.txt", text + "\n");  // a blank line is skipped
  const fs::path gz = owval::testing::TestScratch() / "muscles.txt.gz";
  gzFile out = gzopen(gz.c_str(), "wb");
  gzwrite(out, text.data(), unsigned(text.size()));
  gzclose(out);
  for (const fs::path& path : {plain, gz}) {
    MuscleLogReader reader(path);
    PrintedActivations values{};
    std::size_t lines = 0;
    while (reader.Next(&values)) {
      const MuscleActivations expected = MadeUp(double(lines) * 150);
      for (std::size_t m = 0; m < kLoggedMuscles; ++m)
        EXPECT_NEAR(values[m], expected[m], 5e-7 * std::abs(expected[m])) << path << " " << m;
      ++lines;
    }
    EXPECT_EQ(lines, 3u) << path;
  }
}

TEST(MuscleLog, RefusesWhatIsNotNinetySixFiniteValuesNamingFileAndLine) {
  const std::string good = FormatMuscleLogLine(MadeUp(0));
  std::string short_line = good.substr(0, good.rfind('\t')) + "\n";
  std::string long_line = good.substr(0, good.size() - 1) + "\t1.0\n";
  std::string nan_line = good;
  nan_line.replace(0, nan_line.find('\t'), "nan");
  std::string word_line = good;
  word_line.replace(good.find('\t') + 1, 0, "x");
  std::string comma_line = good;
  comma_line[comma_line.find('.')] = ',';
  const struct {
    std::string text, says;
  } cases[] = {
      {good + short_line, ":2: 95 values; expected 96 finite muscle activations"},
      {long_line, ":1: more than 96 values"},
      {good + good + nan_line, ":3: value 1 is not a finite number"},
      {word_line, ":1: value 2 is not a finite number"},
      {comma_line, ":1: value 1 is not a finite number"},
      {good + std::string(std::size_t{1} << 20 | 1, '1'), ":2: line longer than 1048576 bytes"},
  };
  for (const auto& c : cases) {
    const fs::path path = Write("bad_muscles.txt", c.text);
    const std::string error = ErrorOf(path);
    EXPECT_NE(error.find(path.string() + c.says), std::string::npos) << error;
  }
  EXPECT_NE(ErrorOf(owval::testing::TestScratch() / "absent.txt").find("cannot open"),
            std::string::npos);
}

TEST(MuscleLog, ItsOwnSignalAgreesAndEditsBeyondTheRoundingDoNot) {
  const Trajectory header = Header(20, 150);
  const fs::path own = Write("own.txt", Lines(20, 150));
  const TrackAgreement a = CompareMuscleLogWithSignal(own, header, MadeUp);
  EXPECT_TRUE(a.agrees) << a.detail;
  EXPECT_NE(a.detail.find("20 lines; 0 disagree with owval's muscle signal"), std::string::npos)
      << a.detail;
  // One value's 7th significant digit moved by 2 units: beyond %e's half unit.
  std::string text = Lines(20, 150);
  const std::size_t line7 = [&] {
    std::size_t at = 0;
    for (int i = 0; i < 7; ++i) at = text.find('\n', at) + 1;
    return at;
  }();
  const std::size_t value = text.find('\t', line7) + 1;  // muscle 2 of line 8
  const std::size_t digit = value + 7;                   // d.ddddd[d]e
  text[digit] = text[digit] < '8' ? char(text[digit] + 2) : char(text[digit] - 2);
  const TrackAgreement edited =
      CompareMuscleLogWithSignal(Write("edited.txt", text), header, MadeUp);
  EXPECT_FALSE(edited.agrees);
  EXPECT_NE(edited.detail.find("1 disagree"), std::string::npos) << edited.detail;
  EXPECT_NE(edited.detail.find("at line 8 (step 1050), muscle 2"), std::string::npos)
      << edited.detail;
  // Lines shifted by one: line j holds step (j+1)'s activations.
  std::string shifted = Lines(21, 150);
  shifted.erase(0, shifted.find('\n') + 1);
  EXPECT_FALSE(CompareMuscleLogWithSignal(Write("shifted.txt", shifted), header, MadeUp).agrees);
  // A line missing.
  const TrackAgreement cut =
      CompareMuscleLogWithSignal(Write("cut.txt", Lines(19, 150)), header, MadeUp);
  EXPECT_FALSE(cut.agrees);
  EXPECT_EQ(cut.detail, "19 lines, the trajectory 20 frames");
}

TEST(MuscleLog, ZerosAgreeOnlyBesideATrajectoryThatIsNoWorm) {
  MuscleActivations zero{};
  std::string text;
  for (int f = 0; f < 4; ++f) text += FormatMuscleLogLine(zero);
  const TrackAgreement a =
      CompareMuscleLogWithSignal(Write("zeros.txt", text), Header(4, 150), MadeUp);
  EXPECT_TRUE(a.agrees) << a.detail;
  EXPECT_NE(a.detail.find("all zero"), std::string::npos) << a.detail;
}

TEST(MuscleLog, ATrajectoryWithoutATimeStepIsRefused) {
  Trajectory header = Header(2, 150);
  header.time_step_s = 0;
  EXPECT_THROW(CompareMuscleLogWithSignal(Write("two.txt", Lines(2, 150)), header, MadeUp),
               InputError);
}

}  // namespace
}  // namespace owval::kinematics
