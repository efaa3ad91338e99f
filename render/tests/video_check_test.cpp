// CheckSideBySide (the checklist's item 4): a side-by-side video is held to the two runs it
// claims to show by drawing its frames again with the options recorded in it.
#include "owval/render/video_check.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include "owval/base/errors.hpp"
#include "owval/testing/scratch_directory.hpp"
#include "owval/testing/test_files.hpp"
#include "owval/trajectory/formats.hpp"

namespace owval::render {
namespace {
namespace fs = std::filesystem;

// One elastic particle falling 0.5 cu a frame from `y` in a 30 cu box, 12 frames.
Trajectory Falling(float y) {
  Trajectory t;
  t.box = {0, 30, 0, 30, 0, 30};
  t.time_step_s = 1e-3;
  t.type = {2.1f};
  for (std::size_t f = 0; f < 12; ++f) {
    const float p[3] = {15, y - 0.5f * float(f), 15};
    t.AppendFrame(double(f) * 1e-3, p);
  }
  return t;
}

RenderOptions Small() {
  RenderOptions o;
  o.width = 640;
  o.height = 320;
  o.quiet = true;
  o.title = "falling";
  o.tracking = Track{};
  return o;
}

SideBySideCheck Check(const fs::path& mp4, const Trajectory& ref, const Trajectory& cand) {
  const auto refs = MemoryFrameSource(ref), cands = MemoryFrameSource(cand);
  SideBySideCheckOptions quiet;
  quiet.quiet = true;
  return CheckSideBySide(mp4, *refs, *cands, quiet);
}

class VideoCheck : public ::testing::Test {
 protected:
  fs::path Video(const Trajectory& ref, const Trajectory& cand, const RenderOptions& o = Small()) {
    const fs::path mp4 = dir_.path() / ("sxs" + std::to_string(++videos_) + ".mp4");
    RenderSideBySide(ref, cand, o, mp4);
    return mp4;
  }
  owval::testing::ScratchDirectory dir_{"video_check"};
  int videos_ = 0;
  const Trajectory reference_ = Falling(20), candidate_ = Falling(25);
};

TEST_F(VideoCheck, AVideoOfTheTwoRunsShowsThem) {
  const SideBySideCheck c = Check(Video(reference_, candidate_), reference_, candidate_);
  EXPECT_TRUE(c.pass) << c.detail;
  EXPECT_TRUE(c.recorded);
  EXPECT_EQ(c.video.decoded_frames, 12u);
  EXPECT_EQ(c.frames_compared, 12u);
  // What H.264 (crf 18) leaves between the decoded frames and the frames drawn again (2.69).
  EXPECT_LT(c.worst_block_difference, 5) << c.detail;
}

TEST_F(VideoCheck, AVideoOfOtherRunsDoesNot) {
  const fs::path reference_twice = Video(reference_, reference_);
  const SideBySideCheck c = Check(reference_twice, reference_, candidate_);
  EXPECT_FALSE(c.pass);
  EXPECT_EQ(c.detail.rfind("does not show these two runs", 0), 0u) << c.detail;
  EXPECT_GT(c.worst_block_difference, 30) << c.detail;  // measured 69.6
  // Nor does the right video checked against runs swapped.
  EXPECT_FALSE(Check(Video(reference_, candidate_), candidate_, reference_).pass);
}

// A record is only a recipe: one that names other options than the video was drawn with fails.
TEST_F(VideoCheck, ARecordThatDoesNotDescribeTheVideoFails) {
  RenderOptions o = Small();
  o.max_frames = 6;
  const fs::path six = Video(reference_, candidate_, o);
  EXPECT_TRUE(Check(six, reference_, candidate_).pass);
  if (std::system("command -v ffmpeg > /dev/null") != 0) GTEST_SKIP() << "no ffmpeg";
  o.title = "another title";
  const fs::path retitled = dir_.path() / "retitled.mp4";
  const std::string comment = kSideBySideRecordPrefix + SideBySideRecord(o).dump();
  const std::string remux = "ffmpeg -loglevel error -i '" + six.string() +
                            "' -c copy -metadata comment='" + comment + "' '" + retitled.string() +
                            "'";
  ASSERT_EQ(std::system(remux.c_str()), 0) << remux;
  const SideBySideCheck c = Check(retitled, reference_, candidate_);
  EXPECT_TRUE(c.recorded);
  EXPECT_FALSE(c.pass) << c.detail;
}

TEST_F(VideoCheck, AVideoWithoutOwvalsRecordIsNotHeldToTheRunsAndFails) {
  const fs::path single = dir_.path() / "single.mp4";
  RenderVideo(reference_, Small(), single);  // one panel, no side-by-side record
  const SideBySideCheck c = Check(single, reference_, candidate_);
  EXPECT_FALSE(c.pass);
  EXPECT_FALSE(c.recorded);
  EXPECT_NE(c.detail.find("no owval render record"), std::string::npos) << c.detail;
}

TEST_F(VideoCheck, AVideoDrawnWithConnectionsCannotBeRedrawn) {
  RenderOptions o = Small();
  o.connections = {{0, 0}};
  const SideBySideCheck c = Check(Video(reference_, candidate_, o), reference_, candidate_);
  EXPECT_FALSE(c.pass);
  EXPECT_NE(c.detail.find("1 elastic connections"), std::string::npos) << c.detail;
}

// Options under which no run can be told from another: one_sprig's walls enclose its particle, so
// drawn opaque they hide it; in a 48x32 frame the falling particle is 2 pixels across. Either
// video would show any two runs alike, so neither is held to be a video of these.
TEST_F(VideoCheck, AVideoWhoseOptionsHideTheRunsFails) {
  RenderOptions o = Small();
  o.max_frames = 3;
  o.boundary = BoundaryMode::kShown;
  const fs::path walls = dir_.path() / "walls.mp4";
  const auto sources = [] {
    return std::make_pair(OpenFrameSource(owval::testing::kBundledOneSprig),
                          OpenFrameSource(owval::testing::kBundledOneSprig));
  };
  {
    auto [refs, cands] = sources();
    RenderSideBySide(*refs, *cands, o, walls);
  }
  auto [refs, cands] = sources();
  SideBySideCheckOptions quiet;
  quiet.quiet = true;
  const SideBySideCheck hidden = CheckSideBySide(walls, *refs, *cands, quiet);
  EXPECT_FALSE(hidden.pass);
  EXPECT_NE(hidden.detail.find("do not show the candidate"), std::string::npos) << hidden.detail;
  o.boundary = BoundaryMode::kTranslucent;  // what the pipeline draws
  const fs::path translucent = dir_.path() / "translucent.mp4";
  RenderSideBySide(*refs, *cands, o, translucent);
  const SideBySideCheck shown = CheckSideBySide(translucent, *refs, *cands, quiet);
  EXPECT_TRUE(shown.pass) << shown.detail;

  RenderOptions tiny = Small();
  tiny.width = 48, tiny.height = 32;
  const SideBySideCheck small = Check(Video(reference_, candidate_, tiny), reference_, candidate_);
  EXPECT_FALSE(small.pass);
  EXPECT_NE(small.detail.find("do not show the candidate"), std::string::npos) << small.detail;
}

TEST(SideBySideRecord, RoundTripsEveryOptionThatDecidesThePixels) {
  RenderOptions o;
  o.width = 640, o.height = 320, o.view = "side", o.boundary = BoundaryMode::kTranslucent;
  o.liquid_opacity = 0.35f, o.point_size_px = 7.5f, o.fps = 24, o.max_frames = 300;
  o.title = "one_sprig", o.reference_label = "OpenCL", o.candidate_label = "Metal";
  o.draw_box = false;
  o.tracking = Track{0, "elastic", Axis::kZ};
  const RenderOptions back = OptionsFromSideBySideRecord(SideBySideRecord(o), "sxs.mp4");
  EXPECT_EQ(back.width, 640);
  EXPECT_EQ(back.height, 320);
  EXPECT_EQ(back.view, "side");
  EXPECT_EQ(back.boundary, BoundaryMode::kTranslucent);
  EXPECT_EQ(back.liquid_opacity, 0.35f);
  EXPECT_EQ(back.point_size_px, 7.5f);
  EXPECT_EQ(back.fps, 24);
  EXPECT_EQ(back.max_frames, 300u);
  EXPECT_EQ(back.title, "one_sprig");
  EXPECT_EQ(back.reference_label, "OpenCL");
  EXPECT_EQ(back.candidate_label, "Metal");
  EXPECT_FALSE(back.draw_box);
  ASSERT_TRUE(back.tracking.has_value());
  EXPECT_EQ(back.tracking->Describe(), "elastic centroid z");
}

TEST(SideBySideRecord, ABadFieldIsNamed) {
  nlohmann::json record = SideBySideRecord(RenderOptions{});
  record["view"] = 3;
  try {
    OptionsFromSideBySideRecord(record, "sxs.mp4");
    FAIL() << "accepted a numeric view";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'view'"), std::string::npos) << e.what();
  }
  record = SideBySideRecord(RenderOptions{});
  record["max_frames"] = -1;
  EXPECT_THROW(OptionsFromSideBySideRecord(record, "sxs.mp4"), InputError);
  record = SideBySideRecord(RenderOptions{});
  record["record"] = "owval render sxs/2";
  EXPECT_THROW(OptionsFromSideBySideRecord(record, "sxs.mp4"), InputError);
}

}  // namespace
}  // namespace owval::render
