// The speed's sign (speed_windows.hpp): a window from frame i to frame j is signed by the
// tail-to-head direction at frame (i + j) / 2, not at i or j. The analyser's test compares the
// streamed speeds with a whole-series loop written the same way, so a wrong middle frame in both
// would pass it; here the body turns round at one frame only, and the sign says which frame was
// read.
#include "speed_windows.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace owval::kinematics::internal {
namespace {

// Frames at t = 0, 1, 2, ... s; every part moves +1 mm in x per frame; the head points +x (tail
// at -1 mm, head at +1 mm from the part) except at the frames in `reversed`.
std::vector<PartCentroids> Frames(std::size_t count, const std::vector<std::size_t>& reversed) {
  std::vector<PartCentroids> frames;
  for (std::size_t k = 0; k < count; ++k) {
    const double x = double(k);
    bool backwards = false;
    for (std::size_t r : reversed) backwards |= r == k;
    const double facing = backwards ? -1 : 1;
    PartCentroids c;
    c.time_s = double(k);
    c.head = {x + facing, 0};
    c.midbody = {x, 0};
    c.tail = {x - facing, 0};
    frames.push_back(c);
  }
  return frames;
}

double MidbodySpeed(double window_s, const std::vector<PartCentroids>& frames) {
  SpeedWindows windows(window_s, window_s);
  for (const PartCentroids& f : frames) windows.Observe(f);
  const std::optional<double> speed = windows.MeanSpeed(BodyPart::kMidbody);
  EXPECT_TRUE(speed.has_value());
  return speed.value_or(0);
}

TEST(SpeedWindows, TheSignIsTheBodysDirectionAtTheWindowsMiddleFrame) {
  // One window, frames 0..2: its middle is frame 1.
  EXPECT_EQ(MidbodySpeed(2, Frames(3, {})), 1.0);
  EXPECT_EQ(MidbodySpeed(2, Frames(3, {1})), -1.0);  // turned round at the middle: backwards
  EXPECT_EQ(MidbodySpeed(2, Frames(3, {0})), 1.0);   // not the opening frame's direction
  EXPECT_EQ(MidbodySpeed(2, Frames(3, {2})), 1.0);   // nor the closing frame's
}

TEST(SpeedWindows, AnEvenSpanTakesTheLowerOfTheTwoMiddleFrames) {
  // One window, frames 0..3: (0 + 3) / 2 = 1.
  EXPECT_EQ(MidbodySpeed(3, Frames(4, {1})), -1.0);
  EXPECT_EQ(MidbodySpeed(3, Frames(4, {2})), 1.0);
}

TEST(SpeedWindows, EachWindowIsSignedByItsOwnMiddle) {
  // Windows (0, 2), (1, 3), (2, 4): middles 1, 2, 3; turned round at frame 2 only.
  EXPECT_DOUBLE_EQ(MidbodySpeed(2, Frames(5, {2})), 1.0 / 3.0);
}

}  // namespace
}  // namespace owval::kinematics::internal
