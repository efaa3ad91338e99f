// FrameSource::CopyFrames: one per-frame array, a range of frames at a time (what WriteHdf5 of a
// source copies a dataset at a time). An HDF5 file reads that dataset alone; whatever the source,
// the values are its frames', and WriteHdf5 of any source gives WriteHdf5's bytes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "owval/testing/scratch_directory.hpp"
#include "owval/testing/test_files.hpp"
#include "owval/trajectory/formats.hpp"
#include "owval/trajectory/frame_source.hpp"

namespace owval {
namespace {
namespace fs = std::filesystem;
using testing::FileBytes;
using testing::ScratchFile;

// 41 frames of 5 particles, every value distinct; density holds a NaN (a diverged run's may).
Trajectory FortyOneFramesWithFields() {
  Trajectory t;
  t.box = {0, 10, 0, 10, 0, 10};
  t.time_step_s = 1e-5;
  t.log_step = 2;
  t.type = {1, 1, 2.1f, 2, 3};
  const std::size_t frames = 41, n = t.type.size();
  for (std::size_t f = 0; f < frames; ++f) {
    t.time_s.push_back(double(f) * 2e-5);
    for (std::size_t i = 0; i < n; ++i) {
      const float k = float(f * n + i);
      for (int a = 0; a < 3; ++a) {
        t.positions.push_back(1 + k * 1e-3f + float(a));
        t.velocities.push_back(-k * 1e-2f + float(a));
      }
      t.density.push_back(1000 + k * 0.25f);
      t.pressure.push_back(-k * 0.5f);
    }
  }
  t.density[n + 1] = NAN;
  t.provenance["scenario"] = "copy_frames";
  return t;
}

const std::vector<float>& ArrayOf(const Trajectory& t, const std::string& array) {
  return array == "positions"    ? t.positions
         : array == "velocities" ? t.velocities
         : array == "density"    ? t.density
                                 : t.pressure;
}

TEST(CopyFrames, EveryArrayOfAnHdf5FileEqualsTheWholeReadAcrossChunks) {
  const Trajectory t = FortyOneFramesWithFields();
  const std::size_t n = t.particle_count();
  for (std::size_t chunk : {std::size_t{1}, std::size_t{16}}) {
    const fs::path h5 = ScratchFile("chunk" + std::to_string(chunk) + ".h5");
    Hdf5WriteOptions options;
    options.frames_per_chunk = chunk;
    WriteHdf5(t, h5, options);
    const auto source = OpenFrameSource(h5);
    for (const std::string array : {"positions", "velocities", "density", "pressure"}) {
      const std::size_t values = (array == "density" || array == "pressure" ? 1 : 3) * n;
      // Ranges that start inside a chunk and cross into the next, and the last frames.
      for (const auto& [first, count] :
           std::vector<std::pair<std::size_t, std::size_t>>{{0, 16}, {13, 7}, {30, 11}, {40, 1}}) {
        std::vector<float> out(count * values, 7.0f);
        source->CopyFrames(array, first, count, out.data());
        EXPECT_EQ(std::memcmp(out.data(), ArrayOf(t, array).data() + first * values,
                              out.size() * sizeof(float)),
                  0)
            << array << " frames " << first << "+" << count << ", chunk " << chunk;
      }
    }
    EXPECT_THROW(source->CopyFrames("positions", 40, 2, std::vector<float>(6 * n).data()),
                 std::out_of_range);
  }
}

TEST(CopyFrames, TheDefaultGoesThroughFramesAndRefusesAnArrayTheFramesLack) {
  const Trajectory t = FortyOneFramesWithFields();
  const auto memory = MemoryFrameSource(t);
  std::vector<float> out(3 * 3 * t.particle_count());
  memory->CopyFrames("velocities", 38, 3, out.data());
  EXPECT_EQ(std::memcmp(out.data(), t.velocities.data() + 38 * 3 * t.particle_count(),
                        out.size() * sizeof(float)),
            0);
  Trajectory positions_only = t;
  positions_only.velocities.clear();
  EXPECT_THROW(MemoryFrameSource(positions_only)->CopyFrames("velocities", 0, 1, out.data()),
               std::out_of_range);
}

// `owval convert a.h5 b.h5` is WriteHdf5 of a.h5's frame source: the bytes WriteHdf5 writes.
TEST(CopyFrames, WriteHdf5OfAnHdf5SourceWithFieldsIsByteIdenticalToTheWholeWrite) {
  const Trajectory t = FortyOneFramesWithFields();
  const fs::path whole = ScratchFile("whole.h5"), streamed = ScratchFile("streamed.h5");
  WriteHdf5(t, whole);
  const auto source = OpenFrameSource(whole);
  WriteHdf5(*source, streamed);
  EXPECT_EQ(FileBytes(streamed), FileBytes(whole));
  const Trajectory back = ReadHdf5(streamed);
  EXPECT_EQ(std::memcmp(back.pressure.data(), t.pressure.data(), t.pressure.size() * 4), 0);
}

}  // namespace
}  // namespace owval
