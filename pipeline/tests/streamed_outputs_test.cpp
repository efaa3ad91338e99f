// The outputs written frame by frame (a worm run's worm_motion_log.txt, worm.wcon, OME-Zarr, and
// owval convert in every direction) equal, byte for byte, what the whole-trajectory writers make
// of the same file read whole, on Sibernetic's own worm run; and a corrupt frame midway through a
// convert leaves nothing behind.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>

#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"
#include "owval/kinematics/midline.hpp"
#include "owval/kinematics/worm_track.hpp"
#include "owval/pipeline/run_directory.hpp"
#include "owval/testing/hdf5_damage.hpp"
#include "owval/testing/scratch_directory.hpp"
#include "owval/trajectory/formats.hpp"
#include "owval/trajectory/frame_source.hpp"
#include "owval/trajectory/worm_formats.hpp"

namespace owval::pipeline {
namespace {
namespace fs = std::filesystem;

const fs::path kWorm =
    fs::path(OWVAL_SHARED_DIR) / "reference/worm_alone_0.6s/position_buffer.txt.gz";

fs::path Scratch(const std::string& name) { return owval::testing::TestScratch(name); }

TextReadOptions Quiet() {
  TextReadOptions quiet;
  quiet.quiet = true;
  return quiet;
}

// The first `frames` frames of `t`, with made-up velocities and density (a run's fields).
Trajectory FirstFramesWithFields(const Trajectory& t, std::size_t frames) {
  Trajectory head = t;
  const std::size_t n = t.particle_count();
  head.time_s.resize(frames);
  head.positions.resize(frames * n * 3);
  head.velocities.resize(frames * n * 3);
  for (std::size_t i = 0; i < head.velocities.size(); ++i)
    head.velocities[i] = 0.5f * head.positions[i] - 1.f;
  head.density.resize(frames * n);
  for (std::size_t i = 0; i < head.density.size(); ++i) head.density[i] = 1000.f + float(i % 97);
  return head;
}

TEST(StreamedOutputs, WormWritersEqualTheWholeTrajectoryTextsOnSiberneticsWormRun) {
  if (!fs::exists(kWorm)) GTEST_SKIP() << "needs " << kWorm;
  const Trajectory whole = ReadTrajectory(kWorm, Quiet());
  const std::unique_ptr<FrameSource> frames = OpenFrameSource(kWorm, Quiet());
  const fs::path dir = Scratch("writers");
  const nlohmann::json settings = {{"source", "worm"}};
  kinematics::WormMotionLogWriter log(dir / "worm_motion_log.txt", frames->header());
  kinematics::WormWconWriter wcon(dir / "worm.wcon", frames->header(), settings, "9.9");
  for (std::size_t f = 0; f < frames->frame_count(); ++f) {
    const FrameRef frame = frames->Frame(f);
    log.Append(frame.trajectory, frame.frame);
    wcon.Append(frame.trajectory, frame.frame);
  }
  log.Commit();
  wcon.Commit();
  EXPECT_EQ(ReadWholeFile(dir / "worm_motion_log.txt"), kinematics::WormMotionLog(whole));
  WormTrack track = kinematics::TrackFromTrajectory(whole, settings);
  track.software_version = "9.9";
  ASSERT_EQ(track.time_s.size(), 200u);
  EXPECT_EQ(ReadWholeFile(dir / "worm.wcon"), WconText(track));
}

// Uncompressed, each chunk file is the frames' positions in micrometres, the last one padded.
TEST(StreamedOutputs, ZarrChunksHoldTheFramesAChunkAtATime) {
  if (!fs::exists(kWorm)) GTEST_SKIP() << "needs " << kWorm;
  const Trajectory whole = ReadTrajectory(kWorm, Quiet());
  const std::unique_ptr<FrameSource> frames = OpenFrameSource(kWorm, Quiet());
  const fs::path store = Scratch("zarr") / "worm.zarr";
  ZarrWriteOptions options;
  options.compression_level = 0;
  options.frames_per_chunk = 48;  // 200 frames: 4 whole chunks and one of 8 frames
  OmeZarrWriter zarr(store, frames->header(), options);
  for (std::size_t f = 0; f < frames->frame_count(); ++f) {
    const FrameRef frame = frames->Frame(f);
    zarr.AppendFrame(frame.trajectory.time_s[frame.frame],
                     frame.trajectory.position(frame.frame, 0));
  }
  EXPECT_FALSE(fs::exists(store));  // nothing under the final name before Commit
  zarr.Commit();
  const std::size_t n = whole.particle_count(), per_chunk = 48 * n * 3;
  const float to_um = static_cast<float>(options.simulation_scale_m * 1e6);
  for (std::size_t c = 0; c < 5; ++c) {
    const std::string raw = ReadWholeFile(store / "body/positions" / (std::to_string(c) + ".0.0"));
    ASSERT_EQ(raw.size(), per_chunk * sizeof(float)) << c;
    std::vector<float> values(per_chunk);
    std::memcpy(values.data(), raw.data(), raw.size());
    for (std::size_t i = 0; i < per_chunk; ++i) {
      const std::size_t at = c * per_chunk + i;
      const float expected = at < whole.positions.size() ? whole.positions[at] * to_um : 0.f;
      ASSERT_EQ(values[i], expected) << "chunk " << c << " value " << i;
    }
  }
  EXPECT_FALSE(fs::exists(store / "body/positions/5.0.0"));
  const nlohmann::json shape =
      nlohmann::json::parse(ReadWholeFile(store / "body/positions/.zarray"))["shape"];
  EXPECT_EQ(shape, nlohmann::json({200, n, 3}));
}

TEST(StreamedOutputs, ConvertInEveryDirectionEqualsTheWholeTrajectoryWriters) {
  if (!fs::exists(kWorm)) GTEST_SKIP() << "needs " << kWorm;
  const fs::path dir = Scratch("convert");
  const Trajectory worm = ReadTrajectory(kWorm, Quiet());
  // An HDF5 file with fields, 40 frames: two whole chunks of 16 and a partial one.
  const fs::path h5 = dir / "fields.h5";
  WriteHdf5(FirstFramesWithFields(worm, 40), h5);
  const Trajectory fields = ReadTrajectory(h5, Quiet());
  ASSERT_TRUE(fields.has_velocities() && fields.has_density());

  ConvertTrajectoryFile(h5, Quiet(), dir / "copy.h5", TextLayout::kOpenCL);
  EXPECT_EQ(ReadWholeFile(dir / "copy.h5"), ReadWholeFile(h5));
  ConvertTrajectoryFile(kWorm, Quiet(), dir / "worm.h5", TextLayout::kOpenCL);
  WriteHdf5(worm, dir / "worm_whole.h5");
  EXPECT_EQ(ReadWholeFile(dir / "worm.h5"), ReadWholeFile(dir / "worm_whole.h5"));
  for (TextLayout layout : {TextLayout::kOpenCL, TextLayout::kNative}) {
    ConvertTrajectoryFile(h5, Quiet(), dir / "fields.txt", layout);
    WriteSiberneticText(fields, dir / "fields_whole.txt", layout);
    EXPECT_EQ(ReadWholeFile(dir / "fields.txt"), ReadWholeFile(dir / "fields_whole.txt"))
        << LayoutName(layout);
  }
  ConvertTrajectoryFile(kWorm, Quiet(), dir / "worm.wcon", TextLayout::kOpenCL);
  WriteWormWcon(worm, {{"source", kWorm.string()}}, dir / "worm_whole.wcon");
  EXPECT_EQ(ReadWholeFile(dir / "worm.wcon"), ReadWholeFile(dir / "worm_whole.wcon"));
  ConvertTrajectoryFile(h5, Quiet(), dir / "fields.zarr", TextLayout::kOpenCL);
  WriteOmeZarr(fields, dir / "fields_whole.zarr");
  std::size_t files = 0;
  for (const fs::directory_entry& e : fs::recursive_directory_iterator(dir / "fields_whole.zarr")) {
    if (!e.is_regular_file()) continue;
    const fs::path relative = fs::relative(e.path(), dir / "fields_whole.zarr");
    EXPECT_EQ(ReadWholeFile(dir / "fields.zarr" / relative), ReadWholeFile(e.path())) << relative;
    ++files;
  }
  // .zgroup and .zattrs of the root and of body; positions' .zarray, .zattrs and chunks 0..2;
  // types' and time's .zarray, .zattrs and chunk.
  EXPECT_EQ(files, 2u + 2 + 5 + 3 + 3);
}

using testing::CorruptPositionsChunk;

TEST(StreamedOutputs, ACorruptFrameMidwayThroughAConvertLeavesNoOutput) {
  if (!fs::exists(kWorm)) GTEST_SKIP() << "needs " << kWorm;
  const fs::path dir = Scratch("corrupt");
  const fs::path h5 = dir / "in.h5";
  WriteHdf5(FirstFramesWithFields(ReadTrajectory(kWorm, Quiet()), 40), h5);
  CorruptPositionsChunk(h5, 16);  // frames 0..15 read, then the second chunk fails
  for (const char* out : {"out.txt", "out.h5", "out.zarr", "out.wcon"}) {
    try {
      ConvertTrajectoryFile(h5, Quiet(), dir / out, TextLayout::kOpenCL);
      ADD_FAILURE() << out << ": a corrupt chunk was converted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("in.h5"), std::string::npos) << out << e.what();
    }
    std::vector<std::string> left;
    for (const fs::directory_entry& e : fs::directory_iterator(dir))
      if (e.path().filename() != "in.h5") left.push_back(e.path().filename().string());
    EXPECT_TRUE(left.empty()) << out << " left " << (left.empty() ? "" : left.front());
  }
}

// An HDF5 trajectory of no frame converted to Sibernetic text no reader takes (frame 0 lists the
// walls): refused, naming the file, and nothing written in any format.
TEST(StreamedOutputs, ConvertRefusesATrajectoryOfNoFrame) {
  if (!fs::exists(kWorm)) GTEST_SKIP() << "needs " << kWorm;
  const fs::path dir = Scratch("no_frame");
  const fs::path h5 = dir / "none.h5";
  WriteHdf5(FirstFramesWithFields(ReadTrajectory(kWorm, Quiet()), 0), h5);
  for (const char* out : {"out.txt", "out.h5", "out.zarr", "out.wcon"}) {
    try {
      ConvertTrajectoryFile(h5, Quiet(), dir / out, TextLayout::kOpenCL);
      ADD_FAILURE() << out << ": a trajectory of no frame was converted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("none.h5: holds no frame to convert"), std::string::npos)
          << out << ": " << e.what();
    }
    EXPECT_FALSE(fs::exists(dir / out)) << out;
  }
}

}  // namespace
}  // namespace owval::pipeline
