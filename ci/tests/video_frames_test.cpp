// Item 4 holds sxs.mp4's decoded frame count to the runs it shows: a one-frame "video" (a still)
// of the right shape and codec passed as the side-by-side video of a 2,500-frame run.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include "owval/ci/checklist.hpp"
#include "owval/render/render.hpp"
#include "owval/testing/scratch_directory.hpp"
#include "owval/testing/test_files.hpp"
#include "owval/trajectory/formats.hpp"

namespace owval::ci {
namespace {
namespace fs = std::filesystem;

// What sxs.mp4 is made of: `frames` black frames of `size`, by ffmpeg's encoder `encoder`, or
// owval's side-by-side video of the two runs (`encoder` "owval", `frames` as --max-frames).
struct Video {
  int frames = 5;
  std::string size = "320x160";
  std::string encoder = "libx264";
};

void Encode(const Video& video, const fs::path& run, const fs::path& mp4) {
  if (video.encoder == "owval") {
    const Trajectory t = ReadTrajectory(run);
    render::RenderOptions o;
    render::ParseFrameSize(video.size, &o);
    o.max_frames = std::size_t(video.frames);
    o.quiet = true;
    render::RenderSideBySide(t, t, o, mp4);
    return;
  }
  const std::string encode = "ffmpeg -loglevel error -f lavfi -i color=c=black:s=" + video.size +
                             ":r=30 -frames:v " + std::to_string(video.frames) + " -c:v " +
                             video.encoder + " -pix_fmt yuv420p '" + mp4.string() + "'";
  if (std::system(encode.c_str()) != 0) throw std::runtime_error("ffmpeg failed: " + encode);
}

// Item 4 of a directory with `run` as reference and candidate and that video.
ChecklistItem ItemFour(const Video& video, const fs::path& run = testing::kBundledOneSprig) {
  const fs::path dir = owval::testing::TestScratch("video");
  const std::string extension = run.extension().string();
  fs::copy_file(run, dir / ("reference" + extension));
  fs::copy_file(run, dir / ("candidate" + extension));
  Encode(video, run, dir / "sxs.mp4");
  const ChecklistReport r = RunChecklist(dir);
  return r.items.at(3);
}

bool NoFfmpeg() { return std::system("command -v ffmpeg > /dev/null") != 0; }

TEST(VideoFrames, AOneFrameVideoOfTwoRunsFails) {
  if (NoFfmpeg()) GTEST_SKIP() << "no ffmpeg";
  const ChecklistItem i = ItemFour({.frames = 1});
  EXPECT_FALSE(i.pass);
  EXPECT_NE(i.detail.find("expected 2 to 2500 frames"), std::string::npos) << i.detail;
}

TEST(VideoFrames, OwvalsVideoOfTheTwoRunsPasses) {
  const ChecklistItem i = ItemFour({.frames = 5, .size = "640x320", .encoder = "owval"});
  EXPECT_TRUE(i.pass) << i.detail;
  EXPECT_NE(i.detail.find("5 frames decoded"), std::string::npos) << i.detail;
  EXPECT_NE(i.detail.find("5 frames drawn again from the two runs"), std::string::npos) << i.detail;
}

// Codec, shape and frame count say nothing of what a video shows: five black frames of the right
// shape passed as the side-by-side video of one_sprig (round 7: so did a video of the reference
// twice, or of another scenario). Only a video that carries owval's render record can be held
// to the runs (render/tests/video_check_test.cpp).
TEST(VideoFrames, ABlackVideoOfTheRightShapeFails) {
  if (NoFfmpeg()) GTEST_SKIP() << "no ffmpeg";
  const ChecklistItem i = ItemFour({.frames = 5});
  EXPECT_FALSE(i.pass) << i.detail;
  EXPECT_NE(i.detail.find("5 frames decoded"), std::string::npos) << i.detail;
  EXPECT_NE(i.detail.find("no owval render record"), std::string::npos) << i.detail;
}

// one_sprig's first four frames, as HDF5 in a scratch directory of their own.
fs::path FourFrames() {
  const Trajectory full = ReadTrajectory(testing::kBundledOneSprig);
  Trajectory part;
  part.box = full.box, part.type = full.type;
  part.time_step_s = full.time_step_s, part.log_step = full.log_step;
  for (std::size_t f = 0; f < 4; ++f) part.AppendFrame(full.time_s[f], full.position(f, 0));
  const fs::path file = owval::testing::TestScratch("four_frames") / "four_frames.h5";
  WriteTrajectory(part, file);
  return file;
}

// `owval render sxs` draws one frame per paired frame at most: a video with more frames than the
// runs pair shows something else (mutation audit 2026-11-30: without the upper bound, a 5-frame
// video of two 4-frame runs passed).
TEST(VideoFrames, AVideoWithMoreFramesThanTheRunsPairFails) {
  if (NoFfmpeg()) GTEST_SKIP() << "no ffmpeg";
  const fs::path run = FourFrames();
  const ChecklistItem longer = ItemFour({.frames = 5}, run);
  EXPECT_FALSE(longer.pass) << longer.detail;
  EXPECT_NE(longer.detail.find("expected 2 to 4 frames"), std::string::npos) << longer.detail;
  const ChecklistItem same = ItemFour({.frames = 4, .size = "640x320", .encoder = "owval"}, run);
  EXPECT_TRUE(same.pass) << same.detail;
}

// The item names H.264 (what `owval render sxs` writes): an MPEG-4 part 2 video of the right
// shape and length passed when the codec was not checked (mutation audit 2026-11-30).
TEST(VideoFrames, AVideoInAnotherCodecFails) {
  if (NoFfmpeg()) GTEST_SKIP() << "no ffmpeg";
  const ChecklistItem i = ItemFour({.encoder = "mpeg4"});
  EXPECT_FALSE(i.pass) << i.detail;
  EXPECT_NE(i.detail.find("mpeg4 320x160"), std::string::npos) << i.detail;
  EXPECT_NE(i.detail.find("(expected h264)"), std::string::npos) << i.detail;
}

// Two panels side by side are at least 1.5 times as wide as high: a single 4:3 panel (1.33) fails,
// 3:2 passes. cli/tests/checklist_test.cpp's single panel is square, which a rule of "wider than
// high" also fails (mutation audit 2026-11-30).
TEST(VideoFrames, ASinglePanelWiderThanHighFails) {
  if (NoFfmpeg()) GTEST_SKIP() << "no ffmpeg";
  const ChecklistItem four_by_three = ItemFour({.size = "320x240"});
  EXPECT_FALSE(four_by_three.pass) << four_by_three.detail;
  EXPECT_NE(four_by_three.detail.find("not two panels wide"), std::string::npos)
      << four_by_three.detail;
  const ChecklistItem three_by_two = ItemFour({.size = "480x320", .encoder = "owval"});
  EXPECT_TRUE(three_by_two.pass) << three_by_two.detail;
}

}  // namespace
}  // namespace owval::ci
