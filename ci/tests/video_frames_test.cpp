// Item 4 holds sxs.mp4's decoded frame count to the runs it shows: a one-frame "video" (a still)
// of the right shape and codec passed as the side-by-side video of a 2,500-frame run.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include "owval/ci/checklist.hpp"
#include "owval/testing/scratch_directory.hpp"
#include "owval/testing/test_files.hpp"

namespace owval::ci {
namespace {
namespace fs = std::filesystem;

const fs::path& kOneSprig = testing::kBundledOneSprig;

// Item 4 of a directory with one_sprig as reference and candidate and an H.264 video of
// `frames` black 320x160 frames made by ffmpeg's own encoder (not owval's).
ChecklistItem ItemFour(int frames) {
  const fs::path dir = owval::testing::TestScratch(std::to_string(frames));
  fs::copy_file(kOneSprig, dir / "reference.txt");
  fs::copy_file(kOneSprig, dir / "candidate.txt");
  const std::string encode =
      "ffmpeg -loglevel error -f lavfi -i color=c=black:s=320x160:r=30 -frames:v " +
      std::to_string(frames) + " -c:v libx264 -pix_fmt yuv420p '" + (dir / "sxs.mp4").string() +
      "'";
  if (std::system(encode.c_str()) != 0) throw std::runtime_error("ffmpeg failed: " + encode);
  const ChecklistReport r = RunChecklist(dir);
  return r.items.at(3);
}

TEST(VideoFrames, AOneFrameVideoOfTwoRunsFails) {
  if (std::system("command -v ffmpeg > /dev/null") != 0) GTEST_SKIP() << "no ffmpeg";
  const ChecklistItem i = ItemFour(1);
  EXPECT_FALSE(i.pass);
  EXPECT_NE(i.detail.find("expected 2 to 2500 frames"), std::string::npos) << i.detail;
}

TEST(VideoFrames, AVideoOfSeveralFramesPasses) {
  if (std::system("command -v ffmpeg > /dev/null") != 0) GTEST_SKIP() << "no ffmpeg";
  const ChecklistItem i = ItemFour(5);
  EXPECT_TRUE(i.pass) << i.detail;
  EXPECT_NE(i.detail.find("5 frames decoded"), std::string::npos) << i.detail;
}

}  // namespace
}  // namespace owval::ci
