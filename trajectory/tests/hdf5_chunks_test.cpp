// The parallel chunk reader behind ReadHdf5 and the row reader behind Hdf5FrameReader: same
// values as HDF5's own pipeline, zlib's checksum, a fallback for other layouts, and corrupt chunks
// refused.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>
#include <zlib.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "hdf5_chunks.hpp"
#include "owval/base/errors.hpp"
#include "owval/testing/hdf5_damage.hpp"
#include "owval/testing/scratch_directory.hpp"
#include "owval/testing/test_files.hpp"
#include "owval/trajectory/formats.hpp"
#include "owval/trajectory/frame_source.hpp"
#include "owval/trajectory/writer.hpp"

namespace owval {
namespace {
namespace fs = std::filesystem;
using testing::ScratchFile;

// 37 frames x 2500 particles: three chunks along each axis, the last ones partial.
Trajectory Wandering(std::size_t frames = 37, std::size_t particles = 2500) {
  Trajectory t;
  t.box = {0, 90, 0, 90, 0, 90};
  t.time_step_s = 2e-5;
  t.log_step = 20;
  for (std::size_t p = 0; p < particles; ++p) t.type.push_back(p % 7 == 0 ? 3.1f : 1.1f);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.0f, 90.0f);
  std::vector<float> x(particles * 3);
  for (float& v : x) v = u(rng);
  for (std::size_t f = 0; f < frames; ++f) {
    for (std::size_t i = 0; i < x.size(); i += 2) x[i] += 0.01f * float(f);
    t.AppendFrame(double(f) * 4e-4, x.data());
  }
  return t;
}

// positions read through HDF5's own filter pipeline.
std::vector<float> ReadWithHdf5Pipeline(const fs::path& path, std::size_t values) {
  std::vector<float> out(values);
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t set = H5Dopen2(file, "positions", H5P_DEFAULT);
  EXPECT_GE(H5Dread(set, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()), 0);
  H5Dclose(set);
  H5Fclose(file);
  return out;
}

TEST(Hdf5Chunks, ParallelReadEqualsHdf5sPipeline) {
  for (int level : {0, 4, 9}) {  // 0: stored deflate blocks
    const Trajectory t = Wandering();
    const fs::path path = ScratchFile("wander" + std::to_string(level) + ".h5");
    Hdf5WriteOptions options;
    options.compression_level = level;
    WriteHdf5(t, path, options);
    const Trajectory back = ReadHdf5(path);
    EXPECT_EQ(back.positions, t.positions) << level;
    EXPECT_EQ(back.positions, ReadWithHdf5Pipeline(path, t.positions.size())) << level;
  }
}

TEST(Hdf5Chunks, OwvalFilesTakeTheParallelPathAndOtherLayoutsDoNot) {
  const Trajectory t = Wandering(5, 100);
  const fs::path path = ScratchFile("layout.h5");
  WriteHdf5(t, path);
  std::vector<float> out(t.positions.size());
  internal::FileBytes bytes(path.string());
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  const hid_t set = H5Dopen2(file, "positions", H5P_DEFAULT);
  EXPECT_TRUE(internal::ReadDeflatedChunksInParallel(file, set, &bytes, {5, 100, 3}, out.data()));
  EXPECT_EQ(out, t.positions);
  H5Dclose(set);
  // A contiguous dataset and a deflate-only one (as other tools write them) are left to HDF5.
  const hsize_t dims[3] = {5, 100, 3};
  const hid_t space = H5Screate_simple(3, dims, nullptr);
  const hid_t plain =
      H5Dcreate2(file, "plain", H5T_NATIVE_FLOAT, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  H5Dwrite(plain, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, t.positions.data());
  EXPECT_FALSE(
      internal::ReadDeflatedChunksInParallel(file, plain, &bytes, {5, 100, 3}, out.data()));
  EXPECT_FALSE(internal::DeflatedChunkRows::Open(file, plain, path.string(), {5, 100, 3}));
  const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
  const hsize_t chunk[3] = {2, 50, 3};
  H5Pset_chunk(dcpl, 3, chunk);
  H5Pset_deflate(dcpl, 4);
  const hid_t deflated =
      H5Dcreate2(file, "deflated", H5T_NATIVE_FLOAT, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
  H5Dwrite(deflated, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, t.positions.data());
  EXPECT_FALSE(
      internal::ReadDeflatedChunksInParallel(file, deflated, &bytes, {5, 100, 3}, out.data()));
  EXPECT_FALSE(internal::DeflatedChunkRows::Open(file, deflated, path.string(), {5, 100, 3}));
  // Shuffle and deflate as owval writes them, but a fill value of 7 for the chunks never written
  // (only frames 0-1 are): libhdf5 reads 7 there, where the own paths would write 0.
  const hid_t filled_dcpl = H5Pcreate(H5P_DATASET_CREATE);
  const hsize_t owval_chunk[3] = {2, 100, 3};
  H5Pset_chunk(filled_dcpl, 3, owval_chunk);
  H5Pset_shuffle(filled_dcpl);
  H5Pset_deflate(filled_dcpl, 4);
  const float seven = 7;
  H5Pset_fill_value(filled_dcpl, H5T_NATIVE_FLOAT, &seven);
  const hid_t filled =
      H5Dcreate2(file, "filled", H5T_IEEE_F32LE, space, H5P_DEFAULT, filled_dcpl, H5P_DEFAULT);
  const hsize_t start[3] = {0, 0, 0}, two_frames[3] = {2, 100, 3};
  const hid_t file_space = H5Dget_space(filled);
  H5Sselect_hyperslab(file_space, H5S_SELECT_SET, start, nullptr, two_frames, nullptr);
  const hid_t memory = H5Screate_simple(3, two_frames, nullptr);
  H5Dwrite(filled, H5T_NATIVE_FLOAT, memory, file_space, H5P_DEFAULT, t.positions.data());
  EXPECT_FALSE(
      internal::ReadDeflatedChunksInParallel(file, filled, &bytes, {5, 100, 3}, out.data()));
  EXPECT_FALSE(internal::DeflatedChunkRows::Open(file, filled, path.string(), {5, 100, 3}));
  H5Sclose(memory);
  H5Sclose(file_space);
  H5Dclose(filled);
  H5Pclose(filled_dcpl);
  H5Dclose(deflated);
  H5Dclose(plain);
  H5Pclose(dcpl);
  H5Sclose(space);
  H5Fclose(file);
}

TEST(Hdf5Chunks, CorruptChunkIsRefusedWithTheFileName) {
  const fs::path path = ScratchFile("corrupt.h5");
  WriteHdf5(Wandering(), path);
  ASSERT_NO_FATAL_FAILURE(testing::CorruptPositionsChunk(path, 0));
  try {
    ReadHdf5(path);
    FAIL() << "a corrupt chunk was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("corrupt.h5"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("chunk"), std::string::npos) << e.what();
  }
}

TEST(Hdf5Chunks, TruncatedChunkIsRefusedWithTheFileName) {
  const fs::path path = ScratchFile("truncated_chunk.h5");
  WriteHdf5(Wandering(), path);
  {  // Store the first positions chunk again with only the first half of its bytes.
    const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    const hid_t set = H5Dopen2(file, "positions", H5P_DEFAULT);
    const hsize_t origin[3] = {0, 0, 0};
    hsize_t stored = 0;
    ASSERT_GE(H5Dget_chunk_storage_size(set, origin, &stored), 0);
    ASSERT_GT(stored, 64u);
    std::vector<unsigned char> chunk(stored);
    std::uint32_t filters = 0;
    ASSERT_GE(H5Dread_chunk(set, H5P_DEFAULT, origin, &filters, chunk.data()), 0);
    ASSERT_GE(H5Dwrite_chunk(set, H5P_DEFAULT, filters, origin, stored / 2, chunk.data()), 0);
    H5Dclose(set);
    H5Fclose(file);
  }
  try {
    ReadHdf5(path);
    FAIL() << "a truncated chunk was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("truncated_chunk.h5"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("chunk"), std::string::npos) << e.what();
  }
}

// Hdf5FrameReader reads row after row of chunks (16 frames, every particle) through
// DeflatedChunkRows: 37 frames x 2500 particles make three rows of three chunks, the last ones
// partial, each equal to HDF5's own pipeline, in whatever order the frames are asked for.
TEST(Hdf5Chunks, RowsReadEqualHdf5sPipeline) {
  for (int level : {0, 4}) {
    const Trajectory t = Wandering();
    const fs::path path = ScratchFile("rows" + std::to_string(level) + ".h5");
    Hdf5WriteOptions options;
    options.compression_level = level;
    WriteHdf5(t, path, options);
    const std::vector<float> whole = ReadWithHdf5Pipeline(path, t.positions.size());
    const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    const hid_t set = H5Dopen2(file, "positions", H5P_DEFAULT);
    {
      const auto rows = internal::DeflatedChunkRows::Open(file, set, path.string(), {37, 2500, 3});
      ASSERT_TRUE(rows);
      ASSERT_EQ(rows->frames_per_row(), 16u);
      std::vector<float> out(whole.size(), -1.0f);
      for (std::size_t first : {32, 0, 16}) rows->Read(first, out.data() + first * 2500 * 3);
      EXPECT_EQ(out, whole) << level;
    }
    H5Dclose(set);
    H5Fclose(file);
    const auto source = OpenFrameSource(path);
    for (std::size_t f : {36, 0, 20, 15, 16, 31}) {
      const FrameRef x = source->Frame(f);
      const float* p = x.trajectory.position(x.frame, 0);
      EXPECT_EQ(std::vector<float>(p, p + 2500 * 3),
                std::vector<float>(whole.begin() + std::ptrdiff_t(f * 2500 * 3),
                                   whole.begin() + std::ptrdiff_t((f + 1) * 2500 * 3)))
          << level << ", frame " << f;
    }
  }
}

// A corrupt chunk met while streaming: the frames before it read, then a refusal naming the file
// and the first frame of the chunk's row.
TEST(Hdf5Chunks, CorruptChunkMetWhileStreamingNamesTheFileAndFrame) {
  const fs::path path = ScratchFile("corrupt_row.h5");
  WriteHdf5(Wandering(), path);
  ASSERT_NO_FATAL_FAILURE(testing::CorruptPositionsChunk(path, 16));
  Hdf5FrameReader reader(path);
  std::vector<float> x(2500 * 3);
  EXPECT_NO_THROW(reader.ReadFrame(15, x.data()));
  try {
    reader.ReadFrame(17, x.data());
    FAIL() << "a corrupt chunk was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("corrupt_row.h5"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("cannot read frame 16: a chunk does not inflate"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace owval
