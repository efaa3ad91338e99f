// The worm view frames Sibernetic's worm so that it fills at least half of the panel height,
// measured on the rendered pixels (the box views show it as a small shape).
#include <gtest/gtest.h>

#include <filesystem>

#include "owval/render/render.hpp"
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

}  // namespace
}  // namespace owval::render
