#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "owval/base/errors.hpp"
#include "owval/testing/scratch_directory.hpp"
#include "owval/testing/test_files.hpp"
#include "owval/trajectory/formats.hpp"

namespace owval {
namespace {
namespace fs = std::filesystem;
using testing::ScratchFile;

Trajectory ThirtySevenFramesWithFields() {
  Trajectory t;
  t.box = {-1, 10, 0, 20, 0, 30};
  t.time_step_s = 2e-5;
  t.log_step = 20;
  t.type = {2.1f, 2.3f, 1.1f, 3.0f, 3.1f};
  const std::size_t frames = 37;  // not a multiple of the chunk size
  for (std::size_t f = 0; f < frames; ++f) {
    std::vector<float> x(15);
    for (std::size_t i = 0; i < x.size(); ++i) x[i] = 0.123456789f * static_cast<float>(f * 15 + i);
    t.AppendFrame(static_cast<double>(f) * 20 * 2e-5, x.data());
  }
  t.velocities.resize(t.positions.size());
  for (std::size_t i = 0; i < t.velocities.size(); ++i)
    t.velocities[i] = 1e-3f * static_cast<float>(i);
  t.density.assign(frames * 5, 1000.5f);
  t.pressure.assign(frames * 5, 12.25f);
  t.provenance = {{"producer", "owval test"}, {"scenario", "small"}};
  return t;
}

TEST(Hdf5Format, RoundTripIsExact) {
  const Trajectory t = ThirtySevenFramesWithFields();
  const fs::path path = ScratchFile("rt.h5");
  WriteHdf5(t, path);
  EXPECT_EQ(DetectFormat(path), FileFormat::kHdf5);
  const Trajectory back = ReadTrajectory(path);
  EXPECT_EQ(back.positions, t.positions);
  EXPECT_EQ(back.velocities, t.velocities);
  EXPECT_EQ(back.density, t.density);
  EXPECT_EQ(back.pressure, t.pressure);
  EXPECT_EQ(back.time_s, t.time_s);
  EXPECT_EQ(back.type, t.type);
  EXPECT_EQ(back.log_step, 20);
  EXPECT_DOUBLE_EQ(back.time_step_s, 2e-5);
  EXPECT_FLOAT_EQ(back.box.xmin, -1);
  EXPECT_EQ(back.provenance.at("producer"), "owval test");
  EXPECT_EQ(back.provenance.at("scenario"), "small");
}

TEST(Hdf5Format, OptionalFieldsStayAbsent) {
  Trajectory t = ThirtySevenFramesWithFields();
  t.velocities.clear();
  t.density.clear();
  t.pressure.clear();
  const fs::path path = ScratchFile("bare.h5");
  WriteHdf5(t, path);
  const Trajectory back = ReadHdf5(path);
  EXPECT_FALSE(back.has_velocities());
  EXPECT_FALSE(back.has_density());
  EXPECT_EQ(back.positions, t.positions);
}

TEST(Hdf5Format, TruncatedFileIsRefusedWithItsName) {
  const fs::path path = ScratchFile("full.h5");
  WriteHdf5(ThirtySevenFramesWithFields(), path);
  const fs::path cut = ScratchFile("cut.h5");
  fs::copy_file(path, cut, fs::copy_options::overwrite_existing);
  fs::resize_file(cut, fs::file_size(path) / 2);
  try {
    ReadTrajectory(cut);
    FAIL() << "truncated HDF5 accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cut.h5"), std::string::npos) << e.what();
  }
}

TEST(Hdf5Format, MissingFileIsRefused) {
  EXPECT_THROW(ReadHdf5(ScratchFile("none.h5")), InputError);
}

TEST(Hdf5Format, ConvertsOpenCLTextToHdf5AndBack) {
  const fs::path text = ScratchFile("in.txt");
  WriteSiberneticText(ThirtySevenFramesWithFields(), text, TextLayout::kOpenCL);
  // Boundary particles do not move in the OpenCL layout, so compare against the re-read text.
  const Trajectory from_text = ReadTrajectory(text);
  const fs::path h5 = ScratchFile("conv.h5");
  WriteTrajectory(from_text, h5);
  const Trajectory from_h5 = ReadTrajectory(h5);
  EXPECT_EQ(from_h5.positions, from_text.positions);
  const fs::path text2 = ScratchFile("out.txt");
  WriteTrajectory(from_h5, text2);
  EXPECT_EQ(ReadTrajectory(text2).positions, from_text.positions);
}

}  // namespace
}  // namespace owval
