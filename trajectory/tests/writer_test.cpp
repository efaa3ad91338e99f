// Streaming trajectory output (issue 16's trajectory part): the same bytes as the whole-trajectory
// writers for text, the same values for HDF5, and a readable partial file on Abort.
#include "owval/trajectory/writer.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "owval/base/errors.hpp"
#include "owval/testing/scratch_directory.hpp"
#include "owval/testing/test_files.hpp"
#include "read_errors.hpp"

namespace owval {
namespace {
namespace fs = std::filesystem;
using testing::FileBytes;
using testing::ScratchFile;

// 37 frames (not a multiple of the 16-frame chunk) of 5 particles, boundary last.
Trajectory Moving() {
  Trajectory t;
  t.box = {0, 10, 0, 20, 0, 30};
  t.time_step_s = 2e-5;
  t.log_step = 20;
  t.type = {2.1f, 2.3f, 1.1f, 3.0f, 3.1f};
  std::vector<float> x(15);
  for (std::size_t f = 0; f < 37; ++f) {
    for (std::size_t i = 0; i < 9; ++i) x[i] = 0.123456789f * float(f * 15 + i);
    for (std::size_t i = 9; i < 15; ++i) x[i] = float(i);
    t.AppendFrame(double(f) * 4e-4, x.data());
  }
  return t;
}

TrajectoryHeader HeaderOf(const Trajectory& t) {
  TrajectoryHeader h;
  h.box = t.box, h.time_step_s = t.time_step_s, h.log_step = t.log_step, h.type = t.type;
  return h;
}

void Stream(const Trajectory& t, TrajectoryWriter& w, std::size_t frames) {
  for (std::size_t f = 0; f < frames; ++f) w.AppendFrame(t.time_s[f], t.position(f, 0));
}

TEST(TrajectoryWriter, StreamedTextEqualsWriteSiberneticTextByteForByte) {
  const Trajectory t = Moving();
  for (TextLayout layout : {TextLayout::kOpenCL, TextLayout::kNative}) {
    const fs::path whole = ScratchFile("whole.txt"), streamed = ScratchFile("streamed.txt");
    fs::remove(streamed);
    WriteSiberneticText(t, whole, layout);
    TrajectoryWriterOptions options;
    options.layout = layout;
    auto w = OpenTrajectoryWriter(streamed, HeaderOf(t), options);
    EXPECT_FALSE(fs::exists(streamed));  // nothing under the final name before Close
    Stream(t, *w, t.frame_count());
    w->Close();
    EXPECT_EQ(FileBytes(streamed), FileBytes(whole)) << LayoutName(layout);
  }
}

TEST(TrajectoryWriter, StreamedHdf5ReadsBackEqualAndIdenticalRunsGiveIdenticalBytes) {
  const Trajectory t = Moving();
  const fs::path a = ScratchFile("a.h5"), b = ScratchFile("b.h5");
  for (const fs::path& p : {a, b}) {
    auto w = OpenTrajectoryWriter(p, HeaderOf(t));
    Stream(t, *w, t.frame_count());
    EXPECT_EQ(w->frames_written(), 37u);
    w->Close();
  }
  const Trajectory back = ReadTrajectory(a);
  EXPECT_EQ(back.positions, t.positions);
  EXPECT_EQ(back.time_s, t.time_s);
  EXPECT_EQ(back.type, t.type);
  EXPECT_EQ(back.log_step, 20);
  EXPECT_EQ(back.provenance.count("partial"), 0u);
  EXPECT_EQ(FileBytes(a), FileBytes(b));
}

TEST(TrajectoryWriter, AbortLeavesAReadablePartialFileMarkedPartial) {
  const Trajectory t = Moving();
  const fs::path h5 = ScratchFile("run.h5"), txt = ScratchFile("run.txt");
  for (const fs::path& p : {h5, txt}) {
    auto w = OpenTrajectoryWriter(p, HeaderOf(t));
    Stream(t, *w, 21);  // one whole chunk and 5 buffered frames
    w->Abort();
    EXPECT_FALSE(fs::exists(p));
    EXPECT_TRUE(fs::exists(PartialPath(p))) << PartialPath(p);
  }
  EXPECT_EQ(PartialPath(h5).filename(), "run.partial.h5");
  const Trajectory back = ReadTrajectory(PartialPath(h5));
  EXPECT_EQ(back.frame_count(), 21u);
  EXPECT_EQ(back.provenance.at("partial"), "1");
  EXPECT_EQ(std::vector<float>(back.positions),
            std::vector<float>(t.positions.begin(), t.positions.begin() + 21 * 15));
  const TextReadOptions quiet = testing::QuietReading();
  EXPECT_EQ(ReadTrajectory(PartialPath(txt), quiet).frame_count(), 21u);
}

TEST(TrajectoryWriter, AWriterDestroyedWithoutCloseLeavesNothing) {
  const Trajectory t = Moving();
  const fs::path dir = ScratchFile("drop");
  fs::create_directories(dir);
  for (const char* name : {"t.h5", "t.txt"}) {
    auto w = OpenTrajectoryWriter(dir / name, HeaderOf(t));
    Stream(t, *w, 20);
  }
  EXPECT_TRUE(fs::is_empty(dir));
}

// Checkpoint at frame 21 (16 frames in the HDF5 file, 5 pending), more frames appended, the
// writer then lost (destroyed uncommitted, or aborted): resuming from the checkpoint gives what
// an uninterrupted writer gives, with pressure and velocities too.
TEST(TrajectoryWriter, ResumedFromACheckpointEqualsAnUninterruptedWriter) {
  Trajectory t = Moving();
  const std::size_t n = t.particle_count();
  for (std::size_t i = 0; i < t.frame_count() * n; ++i) t.pressure.push_back(0.5f * float(i));
  t.velocities = t.positions;
  TrajectoryHeader h = HeaderOf(t);
  h.velocities = h.pressure = true;
  auto append = [&](TrajectoryWriter& w, std::size_t from, std::size_t to) {
    for (std::size_t f = from; f < to; ++f)
      w.AppendFrame(t.time_s[f], t.position(f, 0), &t.velocities[f * n * 3], nullptr,
                    &t.pressure[f * n]);
  };
  for (const char* name : {"whole.h5", "whole.txt"}) {
    auto w = OpenTrajectoryWriter(ScratchFile(name), h);
    append(*w, 0, 37);
    w->Close();
  }
  for (bool abort : {false, true}) {
    for (const char* name : {"cut.h5", "cut.txt"}) {
      const fs::path path = ScratchFile(name);
      fs::remove(path), fs::remove(PartialPath(path));
      WriterCheckpoint checkpoint;
      {
        auto w = OpenTrajectoryWriter(path, h);
        append(*w, 0, 21);
        checkpoint = w->Checkpoint();
        append(*w, 21, 37);  // a whole chunk (frames 16-31) goes into the file
        if (abort) w->Abort();
      }
      EXPECT_EQ(checkpoint.frames, 21u);
      auto w = ResumeTrajectoryWriter(path, h, checkpoint);
      EXPECT_EQ(w->frames_written(), 21u);
      append(*w, 21, 37);
      w->Close();
      EXPECT_FALSE(fs::exists(PartialPath(path)));
    }
    EXPECT_EQ(FileBytes(ScratchFile("cut.txt")), FileBytes(ScratchFile("whole.txt"))) << abort;
    const Trajectory whole = ReadHdf5(ScratchFile("whole.h5")),
                     cut = ReadHdf5(ScratchFile("cut.h5"));
    EXPECT_EQ(cut.positions, whole.positions);
    EXPECT_EQ(cut.velocities, whole.velocities);
    EXPECT_EQ(cut.pressure, whole.pressure);
    EXPECT_EQ(cut.time_s, whole.time_s);
    EXPECT_EQ(cut.provenance.count("partial"), 0u);
  }
}

TEST(TrajectoryWriter, ResumeWithoutTheCheckpointedFileSaysWhatIsMissing) {
  WriterCheckpoint checkpoint;
  checkpoint.file = ".gone.h5.tmp.1.0";
  TrajectoryHeader h = HeaderOf(Moving());
  EXPECT_THROW(ResumeTrajectoryWriter(ScratchFile("gone.h5"), h, checkpoint), InputError);
  EXPECT_THROW(ResumeTrajectoryWriter(ScratchFile("gone.txt"), h, checkpoint), InputError);
}

TEST(Hdf5FrameReader, ReadsFrameByFrameEqualToTheWholeRead) {
  const Trajectory t = Moving();
  const fs::path path = ScratchFile("frames.h5");
  auto w = OpenTrajectoryWriter(path, HeaderOf(t));
  Stream(t, *w, t.frame_count());
  w->Abort();
  Hdf5FrameReader reader(PartialPath(path));
  EXPECT_TRUE(reader.partial());
  ASSERT_EQ(reader.frame_count(), 37u);
  EXPECT_EQ(reader.header().type, t.type);
  std::vector<float> frame(15);
  for (std::size_t f = 0; f < 37; ++f) {
    EXPECT_DOUBLE_EQ(reader.ReadFrame(f, frame.data()), t.time_s[f]);
    EXPECT_EQ(frame, std::vector<float>(t.position(f, 0), t.position(f, 0) + 15)) << f;
  }
}

}  // namespace
}  // namespace owval
