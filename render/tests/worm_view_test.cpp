// The worm view frames Sibernetic's worm so that it fills at least half of the panel height,
// measured on the rendered pixels (the box views show it as a small shape).
#include <gtest/gtest.h>

#include <png.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "owval/render/render.hpp"
#include "owval/testing/scratch_directory.hpp"
#include "owval/trajectory/formats.hpp"

namespace owval::render {
namespace {
namespace fs = std::filesystem;

struct Extent {
  int rows = 0;  // from the first to the last row holding an elastic (green) pixel
  double centre_x = 0, centre_y = 0;  // mean pixel position of the elastic pixels
};

Extent ElasticExtent(const std::vector<unsigned char>& rgba, int width, int height) {
  int first = height, last = -1;
  double sx = 0, sy = 0, n = 0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const unsigned char* p = &rgba[(std::size_t(y) * width + x) * 4];
      if (p[1] > p[0] + 60 && p[1] > p[2] + 60) {  // elastic green (0.10, 0.70, 0.25), shaded
        first = std::min(first, y), last = std::max(last, y);
        sx += x, sy += y, ++n;
      }
    }
  if (n == 0) return {};
  return {last - first + 1, sx / n, sy / n};
}

TEST(WormView, TheWormFillsAtLeastHalfThePanelHeightAndStaysCentred) {
  const fs::path file =
      fs::path(OWVAL_SHARED_DIR) / "reference/worm_alone_0.6s/position_buffer.txt.gz";
  if (!fs::exists(file)) GTEST_SKIP() << "no " << file;
  TextReadOptions quiet;
  quiet.quiet = true;
  const Trajectory t = ReadTrajectory(file, quiet);
  RenderOptions o;
  o.width = 640, o.height = 360;
  for (std::size_t frame : {0, 100, 199}) {
    o.view = "worm";
    const Extent worm = ElasticExtent(RenderFrameRgba(t, frame, o), o.width, o.height);
    std::printf("frame %zu: worm view %d of %d rows (%.0f%%), centre (%.0f, %.0f)\n", frame,
                worm.rows, o.height, 100.0 * worm.rows / o.height, worm.centre_x, worm.centre_y);
    EXPECT_GE(worm.rows, o.height / 2) << "frame " << frame;
    EXPECT_NEAR(worm.centre_x, o.width / 2, o.width / 8) << "frame " << frame;
    EXPECT_NEAR(worm.centre_y, o.height / 2, o.height / 8) << "frame " << frame;
    o.view = "iso";
    const Extent iso = ElasticExtent(RenderFrameRgba(t, frame, o), o.width, o.height);
    std::printf("frame %zu: iso view %d rows\n", frame, iso.rows);
    EXPECT_LT(iso.rows, worm.rows);
  }
}

// RGBA pixels of a PNG file, through libpng's simplified API.
std::vector<unsigned char> ReadPng(const fs::path& path, int* width, int* height) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, path.c_str())) return {};
  image.format = PNG_FORMAT_RGBA;
  std::vector<unsigned char> rgba(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, rgba.data(), 0, nullptr)) return {};
  *width = int(image.width), *height = int(image.height);
  return rgba;
}

TEST(WormView, FramesPngShowsTheWormOverHalfThePanelHeightByDefault) {
  const fs::path file =
      fs::path(OWVAL_SHARED_DIR) / "reference/worm_alone_0.6s/position_buffer.txt.gz";
  const fs::path exe = fs::path(OWVAL_BINARY_DIR) / "owval";
  if (!fs::exists(file) || !fs::exists(exe)) GTEST_SKIP() << "needs " << file << " and " << exe;
  const fs::path out = owval::testing::TestScratch() / "frames";
  // No --view: a worm trajectory gets the worm view.
  const std::string command = exe.string() + " --quiet frames " + file.string() + " " +
                              file.string() + " --at 100 --size 1280x720 -o " + out.string() +
                              " > /dev/null";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  int width = 0, height = 0;
  const std::vector<unsigned char> rgba = ReadPng(out / "frame_100.png", &width, &height);
  ASSERT_EQ(width, 1280);
  // The left panel (reference): columns 0..639.
  std::vector<unsigned char> left;
  for (int y = 0; y < height; ++y)
    left.insert(left.end(), rgba.begin() + std::size_t(y) * width * 4,
                rgba.begin() + (std::size_t(y) * width + 640) * 4);
  const Extent worm = ElasticExtent(left, 640, height);
  std::printf("frame_100.png: the worm spans %d of %d rows (%.0f%%)\n", worm.rows, height,
              100.0 * worm.rows / height);
  EXPECT_GE(worm.rows, height / 2);
  fs::remove_all(out);
}

}  // namespace
}  // namespace owval::render
