// Frame sources (frame_source.hpp): every frame of a real reference file, streamed, equals the
// whole-file reader's, bit for bit, in any order; the file readers refuse what ReadTrajectory
// refuses, with the same message.
#include "owval/trajectory/frame_source.hpp"

#include <gtest/gtest.h>
#include <unistd.h>
#include <zlib.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "owval/base/errors.hpp"
#include "owval/testing/scratch_directory.hpp"
#include "owval/testing/test_files.hpp"
#include "owval/trajectory/formats.hpp"

namespace owval {
namespace {
namespace fs = std::filesystem;
using testing::FileBytes;
using testing::ScratchFile;

const fs::path& kOneSprig = testing::kBundledOneSprig;
const fs::path kReference = fs::path(OWVAL_SHARED_DIR) / "reference";

void WriteGzip(const fs::path& path, const std::string& text) {
  gzFile out = gzopen(path.c_str(), "wb");
  ASSERT_NE(out, nullptr);
  ASSERT_EQ(gzwrite(out, text.data(), unsigned(text.size())), int(text.size()));
  gzclose(out);
}

// Header and frames of the source equal the whole trajectory's; frames visited in `order`.
void ExpectSameFrames(const Trajectory& whole, FrameSource& source,
                      const std::vector<std::size_t>& order, bool same_file = true) {
  const Trajectory& h = source.header();
  ASSERT_EQ(h.frame_count(), whole.frame_count());
  ASSERT_EQ(h.type, whole.type);
  EXPECT_EQ(h.time_s, whole.time_s);
  EXPECT_EQ(h.time_step_s, whole.time_step_s);
  EXPECT_EQ(h.log_step, whole.log_step);
  EXPECT_EQ(std::memcmp(&h.box, &whole.box, sizeof(Box)), 0);
  if (same_file) {
    EXPECT_EQ(h.provenance, whole.provenance);
  }
  const std::size_t n = whole.particle_count();
  for (std::size_t f : order) {
    const FrameRef frame = source.Frame(f);
    ASSERT_EQ(frame.trajectory.time_s[frame.frame], whole.time_s[f]);
    ASSERT_EQ(std::memcmp(frame.trajectory.position(frame.frame, 0), whole.position(f, 0),
                          n * 3 * sizeof(float)),
              0)
        << "frame " << f;
  }
}

std::vector<std::size_t> Forward(std::size_t frames) {
  std::vector<std::size_t> order;
  for (std::size_t f = 0; f < frames; ++f) order.push_back(f);
  return order;
}

// Forward, then a few jumps back and forth (a seek, a rewind, the same frame twice).
std::vector<std::size_t> Jumping(std::size_t frames) {
  std::vector<std::size_t> order = Forward(frames);
  for (std::size_t f : {frames - 1, frames / 2, frames / 2, std::size_t{0}, frames / 3, frames - 1})
    order.push_back(f);
  return order;
}

void ExpectStreamEqualsWhole(const fs::path& path) {
  TextReadReport whole_report, stream_report;
  const Trajectory whole = ReadTrajectory(path, {}, &whole_report);
  const auto source = OpenFrameSource(path, {}, &stream_report);
  ExpectSameFrames(whole, *source, Jumping(whole.frame_count()));
  EXPECT_EQ(stream_report.description, whole_report.description);
  EXPECT_EQ(stream_report.rows, whole_report.rows);
  EXPECT_EQ(stream_report.bytes, whole_report.bytes);
  EXPECT_EQ(stream_report.detected, whole_report.detected);
}

TEST(FrameSource, OneSprigTextStreamsTheWholeReadersFrames) { ExpectStreamEqualsWhole(kOneSprig); }

TEST(FrameSource, Demo1OpenClLayoutStreamsTheWholeReadersFrames) {
  // Later frames list only the 343 moving particles: the 17,498 boundary rows come from frame 0.
  ExpectStreamEqualsWhole(kReference / "demo1/position_buffer.txt");
}

TEST(FrameSource, GzipCompressedReferenceStreamsTheWholeReadersFrames) {
  ExpectStreamEqualsWhole(kReference / "test_energy/position_buffer.txt.gz");
}

TEST(FrameSource, NativeLayoutAndHdf5StreamTheWholeReadersFrames) {
  // demo1's first 60 frames: in the native layout every frame carries its 17,498 boundary rows.
  Trajectory demo1 = ReadTrajectory(kReference / "demo1/position_buffer.txt");
  demo1.time_s.resize(60);
  demo1.positions.resize(60 * demo1.particle_count() * 3);
  const fs::path native = ScratchFile("demo1_native.txt"), h5 = ScratchFile("demo1.h5");
  WriteSiberneticText(demo1, native, TextLayout::kNative);
  WriteHdf5(demo1, h5);
  ExpectStreamEqualsWhole(native);
  ExpectStreamEqualsWhole(h5);
}

// one_sprig's frames with made-up fields, each value distinct (frame, particle, component).
Trajectory WithFields(std::size_t frames) {
  Trajectory t = ReadTrajectory(kOneSprig);
  t.time_s.resize(frames);
  t.positions.resize(frames * t.particle_count() * 3);
  const std::size_t n = t.particle_count();
  for (std::size_t i = 0; i < frames * n; ++i) {
    for (int a = 0; a < 3; ++a) t.velocities.push_back(float(i) * 1e-3f + float(a));
    t.density.push_back(1000.0f + float(i) * 0.25f);
    t.pressure.push_back(-float(i) * 0.5f);
  }
  if (n > 1) t.density[n + 1] = NAN;  // a field may hold NaN (a diverged run's): passed on
  return t;
}

// Velocities, density and pressure come with each frame once asked for (ReadFields), equal to
// the whole read's, across chunk boundaries and in any order; before that, positions only.
TEST(FrameSource, Hdf5FieldsStreamOnRequestEqualToTheWholeRead) {
  const Trajectory t = WithFields(37);
  const std::size_t n = t.particle_count();
  for (std::size_t chunk : {std::size_t{1}, std::size_t{16}}) {
    const fs::path h5 = ScratchFile("fields_" + std::to_string(chunk) + ".h5");
    Hdf5WriteOptions options;
    options.frames_per_chunk = chunk;
    WriteHdf5(t, h5, options);
    const Trajectory whole = ReadHdf5(h5);
    const auto source = OpenFrameSource(h5);
    EXPECT_FALSE(source->Frame(3).trajectory.has_density());
    source->ReadFields();
    for (std::size_t f : Jumping(37)) {
      const FrameRef x = source->Frame(f);
      const Trajectory& one = x.trajectory;
      ASSERT_TRUE(one.has_velocities() && one.has_density() && one.has_pressure());
      EXPECT_EQ(std::memcmp(&one.velocities[x.frame * n * 3], &whole.velocities[f * n * 3],
                            n * 3 * sizeof(float)),
                0)
          << f;
      EXPECT_EQ(std::memcmp(&one.density[x.frame * n], &whole.density[f * n], n * sizeof(float)), 0)
          << f;
      EXPECT_EQ(std::memcmp(&one.pressure[x.frame * n], &whole.pressure[f * n], n * sizeof(float)),
                0)
          << f;
    }
  }
}

TEST(FrameSource, FilesWithoutFieldsGiveNoneWhenAsked) {
  Trajectory t = WithFields(5);
  t.velocities.clear(), t.pressure.clear();
  const fs::path h5 = ScratchFile("density_only.h5");
  WriteHdf5(t, h5);
  for (const fs::path& path : {h5, kOneSprig}) {
    const auto source = OpenFrameSource(path);
    source->ReadFields();
    const Trajectory& one = source->Frame(1).trajectory;
    EXPECT_FALSE(one.has_velocities()) << path;
    EXPECT_FALSE(one.has_pressure()) << path;
    EXPECT_EQ(one.has_density(), path == h5) << path;
  }
}

TEST(FrameSource, MemorySourceHandsOutTheTrajectoryItself) {
  const Trajectory t = ReadTrajectory(kOneSprig);
  const auto source = MemoryFrameSource(t);
  EXPECT_EQ(&source->header(), &t);
  EXPECT_EQ(&source->Frame(7).trajectory, &t);
  EXPECT_EQ(source->Frame(7).frame, 7u);
  EXPECT_THROW(source->Frame(t.frame_count()), std::out_of_range);
}

TEST(FrameSource, ForcedLayoutAndPartialNameAreHonoured) {
  const fs::path partial = ScratchFile("position_buffer.partial.txt");
  fs::copy_file(kOneSprig, partial, fs::copy_options::overwrite_existing);
  TextReadOptions opencl;
  opencl.layout = TextLayout::kOpenCL;
  const Trajectory whole = ReadTrajectory(partial, opencl);
  const auto source = OpenFrameSource(partial, opencl);
  EXPECT_TRUE(source->partial());
  ExpectSameFrames(whole, *source, Forward(whole.frame_count()));
}

// The message ReadTrajectory gives for a file, or "" when it reads it.
std::string WholeError(const fs::path& path) {
  try {
    ReadTrajectory(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::string StreamError(const fs::path& path) {
  try {
    OpenFrameSource(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(FrameSource, RefusesWhatTheWholeReaderRefusesWithTheSameMessage) {
  const std::string text = FileBytes(kOneSprig);
  std::string nan = text;
  nan.replace(nan.find("17.535\t20.04"), 6, "nan");
  std::string counts = text;
  counts.replace(counts.find("\n1\n"), 3, "\n2\n");  // elastic count 1 -> 2
  const std::pair<const char*, std::string> cases[] = {
      {"cut.txt", text.substr(0, text.size() / 2 - 7)},         // mid-row
      {"short.txt", text.substr(0, text.find('\n', 300) + 1)},  // not a whole frame
      {"header.txt", text.substr(0, 30)},                       // inside the header
      {"nan.txt", nan},                                         // a NaN position
      {"counts.txt", counts},                                   // header counts disagree
      {"empty.txt", ""},
      {"fields.txt", "0\n1\n0\n1\n0\n1\n1\n0\n0\n2e-5\n1\n1 2 3 2.1 9\n"}};  // extra field
  for (const auto& [name, content] : cases) {
    const fs::path path = ScratchFile(name);
    std::ofstream(path, std::ios::binary) << content;
    const std::string expected = WholeError(path);
    ASSERT_FALSE(expected.empty()) << name;
    EXPECT_EQ(StreamError(path), expected) << name;
  }
}

TEST(FrameSource, RefusesATruncatedOrCorruptGzipFile) {
  const std::string text = FileBytes(kOneSprig);
  const fs::path gz = ScratchFile("one_sprig.txt.gz");
  WriteGzip(gz, text);
  const std::string packed = FileBytes(gz);
  const fs::path cut = ScratchFile("cut.txt.gz"), corrupt = ScratchFile("corrupt.txt.gz");
  std::ofstream(cut, std::ios::binary) << packed.substr(0, packed.size() / 2);
  std::string flipped = packed;
  for (std::size_t i = 100; i < 140; ++i) flipped[i] = char(flipped[i] ^ 0x5a);
  std::ofstream(corrupt, std::ios::binary) << flipped;
  EXPECT_NE(StreamError(cut).find("gzip: truncated file"), std::string::npos) << StreamError(cut);
  EXPECT_NE(StreamError(corrupt).find("gzip: corrupt compressed data"), std::string::npos)
      << StreamError(corrupt);
  const auto source = OpenFrameSource(gz);
  ExpectSameFrames(ReadTrajectory(kOneSprig), *source, {0, 1, 2499, 3}, false);
}

}  // namespace
}  // namespace owval
