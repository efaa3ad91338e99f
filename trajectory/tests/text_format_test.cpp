#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <zlib.h>

#include "owval/base/errors.hpp"
#include "owval/testing/scratch_directory.hpp"
#include "owval/testing/test_files.hpp"
#include "owval/trajectory/formats.hpp"

namespace owval {
namespace {
namespace fs = std::filesystem;
using testing::ScratchFile;

// Two elastic/liquid particles and two boundary particles, three frames.
Trajectory SmallTrajectory() {
  Trajectory t;
  t.box = {0, 10, 0, 20, 0, 30};
  t.time_step_s = 2e-5;
  t.log_step = 10;
  t.type = {2.1f, 1.1f, 3.0f, 3.0f};
  for (int f = 0; f < 3; ++f) {
    const float frame[12] = {1.5f + f, 2.25f, 3.0f, 4.0f, 5.0f - f * 0.5f, 6.0f,
                             0.5f,     0.5f,  0.5f, 9.5f, 19.5f,           29.5f};
    t.AppendFrame(f * 10 * 2e-5, frame);
  }
  return t;
}

const char* kHeader = "0\n10\n0\n20\n0\n30\n1\n1\n2\n2e-05\n10\n";
const char* kFrame0 = "1.5\t2.25\t3\t2.1\n4\t5\t6\t1.1\n0.5\t0.5\t0.5\t3\n9.5\t19.5\t29.5\t3\n";

Trajectory Parse(const std::string& text, TextLayout layout = TextLayout::kAuto,
                 TextReadReport* report = nullptr) {
  TextReadOptions options;
  options.layout = layout;
  return ParseSiberneticText(text, "mem.txt", options, report);
}

std::string ErrorOf(const std::string& text, TextLayout layout = TextLayout::kAuto) {
  return testing::InputErrorOf([&] { Parse(text, layout); });
}

TEST(TextFormat, ReadsOpenCLLayoutAndFillsBoundaryFromFrameZero) {
  const std::string text = std::string(kHeader) + kFrame0 + "2.5\t2.25\t3\t2.1\n4\t4.5\t6\t1.1\n";
  TextReadReport report;
  const Trajectory t = Parse(text, TextLayout::kAuto, &report);
  EXPECT_EQ(report.detected, TextLayout::kOpenCL);
  ASSERT_EQ(t.frame_count(), 2u);
  ASSERT_EQ(t.particle_count(), 4u);
  EXPECT_FLOAT_EQ(t.coordinate(1, 0, 0), 2.5f);
  EXPECT_FLOAT_EQ(t.coordinate(1, 1, 1), 4.5f);
  EXPECT_FLOAT_EQ(t.coordinate(1, 3, 2), 29.5f);  // boundary repeated
  EXPECT_DOUBLE_EQ(t.time_s[1], 10 * 2e-5);
  EXPECT_EQ(t.count(ParticleKind::kBoundary), 2u);
  EXPECT_NE(report.description.find("opencl"), std::string::npos);
}

// Writes `text` gzip-compressed, cut to `keep` of its compressed bytes (1 = whole).
fs::path WriteGzipCut(const std::string& name, const std::string& text, double keep = 1) {
  const fs::path path = ScratchFile(name);
  gzFile out = gzopen(path.c_str(), "wb");
  gzwrite(out, text.data(), unsigned(text.size()));
  gzclose(out);
  if (keep < 1) fs::resize_file(path, std::uintmax_t(double(fs::file_size(path)) * keep));
  return path;
}

TEST(TextFormat, ReadsGzipCompressedFilesAsTheyAre) {
  const std::string text = std::string(kHeader) + kFrame0 + "2.5\t2.25\t3\t2.1\n4\t4.5\t6\t1.1\n";
  const Trajectory plain = Parse(text);
  const Trajectory unzipped = ReadTrajectory(WriteGzipCut("small.txt.gz", text));
  EXPECT_EQ(unzipped.positions, plain.positions);
  EXPECT_EQ(unzipped.type, plain.type);
}

TEST(TextFormat, TruncatedGzipIsRefusedWithItsName) {
  std::string text = kHeader;
  for (int i = 0; i < 2000; ++i) text += kFrame0;
  const fs::path cut = WriteGzipCut("cut.txt.gz", text, 0.5);
  try {
    ReadTrajectory(cut);
    FAIL() << "truncated gzip accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cut.txt.gz"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos) << e.what();
  }
}

TEST(TextFormat, ReadsNativeLayout) {
  const std::string text = std::string(kHeader) + kFrame0 + kFrame0 + kFrame0;
  TextReadReport report;
  const Trajectory t = Parse(text, TextLayout::kAuto, &report);
  EXPECT_EQ(report.detected, TextLayout::kNative);
  EXPECT_EQ(t.frame_count(), 3u);
}

TEST(TextFormat, TypesDecideWhenBothLayoutsFitTheCounts) {
  // 4 + 2k rows fits opencl for every k; 8 rows also fits native (2 frames of 4).
  const std::string opencl = std::string(kHeader) + kFrame0 + "1\t1\t1\t2.1\n2\t2\t2\t1.1\n" +
                             "1\t1\t1\t2.1\n2\t2\t2\t1.1\n";
  TextReadReport report;
  EXPECT_EQ(Parse(opencl, TextLayout::kAuto, &report).frame_count(), 3u);
  EXPECT_EQ(report.detected, TextLayout::kOpenCL);
  const std::string native = std::string(kHeader) + kFrame0 + kFrame0;
  EXPECT_EQ(Parse(native, TextLayout::kAuto, &report).frame_count(), 2u);
  EXPECT_EQ(report.detected, TextLayout::kNative);
}

TEST(TextFormat, ForcedLayoutOverridesDetection) {
  const std::string text = std::string(kHeader) + kFrame0 + kFrame0;
  TextReadReport report;
  const Trajectory t = Parse(text, TextLayout::kOpenCL, &report);
  EXPECT_EQ(report.detected, TextLayout::kOpenCL);
  EXPECT_EQ(t.frame_count(), 3u);
}

TEST(TextFormat, RefusesRowsFittingNeitherLayoutAndNamesCountsAndOption) {
  const std::string text = std::string(kHeader) + kFrame0 + "1\t1\t1\t2.1\n";
  const std::string error = ErrorOf(text);
  EXPECT_NE(error.find("mem.txt"), std::string::npos) << error;
  EXPECT_NE(error.find("5 position rows"), std::string::npos) << error;
  EXPECT_NE(error.find("--layout"), std::string::npos) << error;
}

TEST(TextFormat, RejectsTruncatedFrameWithForcedLayout) {
  const std::string text = std::string(kHeader) + kFrame0 + kFrame0 + "1\t1\t1\t2.1\n";
  EXPECT_NE(ErrorOf(text, TextLayout::kNative).find("incomplete"), std::string::npos);
}

TEST(TextFormat, RejectsTruncatedLastRowWithLineNumber) {
  const std::string text = std::string(kHeader) + kFrame0 + "1\t1\n";
  const std::string error = ErrorOf(text);
  EXPECT_NE(error.find("mem.txt:16:"), std::string::npos) << error;
  EXPECT_NE(error.find("expected z"), std::string::npos) << error;
}

TEST(TextFormat, RejectsRowCutInsideItsLastNumber) {
  // "1.1" cut to "1" still parses as a number: the missing newline gives it away.
  const std::string text = std::string(kHeader) + kFrame0 + "2.5\t2.25\t3\t2.1\n4\t4.5\t6\t1";
  const std::string error = ErrorOf(text);
  EXPECT_NE(error.find("mem.txt:17:"), std::string::npos) << error;
  EXPECT_NE(error.find("truncated"), std::string::npos) << error;
}

TEST(TextFormat, RejectsTruncatedHeader) {
  EXPECT_NE(ErrorOf("0\n10\n0\n20\n").find("truncated header"), std::string::npos);
}

TEST(TextFormat, RejectsTruncatedFirstFrame) {
  const std::string text = std::string(kHeader) + "1.5\t2.25\t3\t2.1\n";
  EXPECT_NE(ErrorOf(text).find("truncated first frame"), std::string::npos);
}

TEST(TextFormat, RejectsNonNumericFieldWithLineAndValue) {
  const std::string text = std::string(kHeader) + "1.5\tabc\t3\t2.1\n";
  const std::string error = ErrorOf(text);
  EXPECT_NE(error.find("mem.txt:12:"), std::string::npos) << error;
  EXPECT_NE(error.find("expected y, found 'abc'"), std::string::npos) << error;
}

// A NaN or an infinity as a coordinate is a failed simulation's record (exit 1); in the type
// column, or any other field, it is a malformed file (exit 2).
TEST(TextFormat, RejectsNaN) {
  for (const char* row : {"1.5\tnan\t3\t2.1\n", "1.5\t2\t-inf\t2.1\n"}) {
    const std::string text = std::string(kHeader) + row;
    const std::string error = ErrorOf(text);
    EXPECT_NE(error.find("mem.txt:12:"), std::string::npos) << error;
    EXPECT_NE(error.find("not finite (NaN or Inf): the simulation that wrote this file failed"),
              std::string::npos)
        << error;
    EXPECT_THROW(Parse(text, TextLayout::kAuto), NonFiniteTrajectoryError) << row;
  }
  const std::string type = std::string(kHeader) + "1.5\t2\t3\tnan\n";
  EXPECT_NE(ErrorOf(type).find("mem.txt:12:"), std::string::npos) << ErrorOf(type);
  try {
    Parse(type, TextLayout::kAuto);
    ADD_FAILURE() << "a NaN type code was read";
  } catch (const NonFiniteTrajectoryError& e) {
    ADD_FAILURE() << "a NaN type code read as a failed simulation: " << e.what();
  } catch (const InputError&) {
  }
}

TEST(TextFormat, RejectsWrongParticleCounts) {
  std::string header = kHeader;
  header.replace(header.find("1\n1\n2\n"), 6, "2\n0\n2\n");
  const std::string error = ErrorOf(header + kFrame0);
  EXPECT_NE(error.find("wrong particle counts"), std::string::npos) << error;
}

TEST(TextFormat, RejectsEmptyFile) { EXPECT_NE(ErrorOf("").find("empty file"), std::string::npos); }

TEST(TextFormat, RejectsExtraField) {
  const std::string text = std::string(kHeader) + "1.5\t2\t3\t2.1\t7\n";
  EXPECT_NE(ErrorOf(text).find("extra field"), std::string::npos);
}

TEST(TextFormat, MissingFileIsAnInputErrorNamingTheFile) {
  try {
    ReadSiberneticText("/nonexistent/position_buffer.txt");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/position_buffer.txt"), std::string::npos);
  }
}

TEST(TextFormat, WriteThenReadRoundTripsBothLayouts) {
  const Trajectory t = SmallTrajectory();
  for (TextLayout layout : {TextLayout::kOpenCL, TextLayout::kNative}) {
    const fs::path path = ScratchFile(std::string("rt_") + LayoutName(layout) + ".txt");
    WriteSiberneticText(t, path, layout);
    TextReadReport report;
    const Trajectory back = ReadSiberneticText(path, {}, &report);
    EXPECT_EQ(report.detected, layout);
    EXPECT_EQ(back.positions, t.positions);
    EXPECT_EQ(back.type, t.type);
    EXPECT_EQ(back.log_step, t.log_step);
    EXPECT_DOUBLE_EQ(back.time_step_s, t.time_step_s);
  }
}

TEST(TextFormat, WritesSixSignificantDigitsLikeSibernetic) {
  Trajectory t = SmallTrajectory();
  t.positions[0] = 17.5351234f;
  const fs::path path = ScratchFile("digits.txt");
  WriteSiberneticText(t, path, TextLayout::kOpenCL);
  std::ifstream in(path);
  std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(all.substr(0, std::string(kHeader).size()), kHeader);
  EXPECT_NE(all.find("17.5351\t2.25\t3\t2.1\n"), std::string::npos);
}

TEST(TextFormat, FailedWriteLeavesNoPartialFile) {
  Trajectory t = SmallTrajectory();
  t.type = {3.0f, 2.1f, 1.1f, 3.0f};  // boundary first: opencl layout impossible
  const fs::path path = ScratchFile("refused.txt");
  EXPECT_THROW(WriteSiberneticText(t, path, TextLayout::kOpenCL), InputError);
  EXPECT_FALSE(fs::exists(path));
  for (const auto& entry : fs::directory_iterator(path.parent_path()))
    EXPECT_EQ(entry.path().filename().string().find(".refused.txt.tmp"), std::string::npos);
}

}  // namespace
}  // namespace owval
