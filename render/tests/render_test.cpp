#include "owval/render/render.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "owval/base/errors.hpp"
#include "owval/render/read_back.hpp"
#include "owval/testing/scratch_directory.hpp"
#include "owval/testing/test_files.hpp"
#include "owval/trajectory/formats.hpp"

namespace owval::render {
namespace {
namespace fs = std::filesystem;

fs::path Scratch() { return owval::testing::TestScratch(); }

Trajectory OneParticle(float x, float y, float z, std::size_t frames = 1) {
  Trajectory t;
  t.box = {0, 30, 0, 30, 0, 30};
  t.time_step_s = 1e-3;
  t.type = {2.1f};
  for (std::size_t f = 0; f < frames; ++f) {
    const float p[3] = {x, y + 0.1f * float(f), z};
    t.AppendFrame(double(f) * 1e-3, p);
  }
  return t;
}

TEST(Render, ParticleAppearsWhereTheCameraProjectsIt) {
  RenderOptions o;
  o.width = 320;
  o.height = 240;
  o.point_size_px = 12;
  o.draw_box = false;
  const Trajectory t = OneParticle(8, 20, 12);
  const auto rgba = RenderFrameRgba(t, 0, o);
  const Camera camera = Camera::FromBox(t.box, o.view, float(o.width) / o.height);
  const auto at = camera.Project({8, 20, 12}, o.width, o.height);
  auto pixel = [&](int x, int y) { return &rgba[(std::size_t(y) * o.width + x) * 4]; };
  const unsigned char* hit = pixel(int(at[0]), int(at[1]));
  EXPECT_GT(hit[1], hit[0] + 40) << "elastic particles are green";
  EXPECT_GT(hit[1], hit[2] + 40);
  const unsigned char* corner = pixel(5, 5);
  EXPECT_EQ(corner[0], 250);  // background
  EXPECT_EQ(corner[1], 250);
  // The far side of the box, where nothing is drawn, is background too.
  const auto empty = camera.Project({25, 5, 25}, o.width, o.height);
  EXPECT_EQ(pixel(int(empty[0]), int(empty[1]))[1], 250);
}

TEST(Render, TheBoxFloorIsDrawnUnlessTurnedOff) {
  RenderOptions o;
  o.width = 320;
  o.height = 240;
  const Trajectory t = OneParticle(8, 20, 12);
  const Camera camera = Camera::FromBox(t.box, o.view, float(o.width) / o.height);
  const auto floor =
      camera.Project({t.box.xmax * 0.75f, t.box.ymin, t.box.zmax * 0.75f}, o.width, o.height);
  auto green_at = [&](const std::vector<unsigned char>& rgba) {
    return rgba[(std::size_t(floor[1]) * o.width + std::size_t(floor[0])) * 4 + 1];
  };
  EXPECT_LT(green_at(RenderFrameRgba(t, 0, o)), 250);  // tinted by the floor
  o.draw_box = false;
  EXPECT_EQ(green_at(RenderFrameRgba(t, 0, o)), 250);  // background
}

TEST(Render, SideBySideMp4ReadsBackAsH264WithTheExpectedShape) {
  const Trajectory ref = OneParticle(15, 10, 15, 40), cand = OneParticle(15, 11, 15, 40);
  RenderOptions o;
  o.width = 640;
  o.height = 360;
  o.fps = 20;
  o.quiet = true;
  const fs::path mp4 = Scratch() / "sxs.mp4";
  const VideoSummary s = RenderSideBySide(ref, cand, o, mp4);
  EXPECT_EQ(s.frames, 40u);
  const VideoInfo v = ProbeVideo(mp4);
  EXPECT_EQ(v.codec, "h264");
  EXPECT_EQ(v.width, 640);
  EXPECT_EQ(v.height, 360);
  EXPECT_EQ(v.decoded_frames, 40u);
  EXPECT_NEAR(v.duration_s, 2.0, 0.1);
}

TEST(Render, PanelsArePairedByTimeNotIndex) {
  Trajectory coarse = OneParticle(15, 10, 15, 10);
  for (std::size_t f = 0; f < coarse.frame_count(); ++f)
    coarse.time_s[f] = double(f) * 4e-3;                // log step 4x: 0, 4, ..., 36 ms
  const Trajectory fine = OneParticle(15, 10, 15, 40);  // 0, 1, ..., 39 ms
  RenderOptions o;
  o.width = 320;
  o.height = 240;
  o.quiet = true;
  // PairFramesByTime's rule: only the ten moments both runs recorded become video frames.
  const VideoSummary s = RenderSideBySide(coarse, fine, o, Scratch() / "paired.mp4");
  EXPECT_EQ(s.frames, 10u);
  Trajectory disjoint = fine;
  for (double& t : disjoint.time_s) t += 1.0;
  EXPECT_THROW(RenderSideBySide(coarse, disjoint, o, Scratch() / "none.mp4"), InputError);
  EXPECT_FALSE(fs::exists(Scratch() / "none.mp4"));
}

TEST(Render, FramesPrintTheTrajectoryValues) {
  const fs::path one_sprig = owval::testing::kBundledOneSprig;
  const Trajectory t = ReadTrajectory(one_sprig);
  RenderOptions o;
  o.width = 640;
  o.height = 360;
  o.tracking = Track{0, "", Axis::kY};
  const auto json = RenderFrames(t, t, {0, 15, 100}, o, Scratch() / "frames");
  ASSERT_EQ(json["frames"].size(), 3u);
  EXPECT_FLOAT_EQ(json["frames"][1]["reference_value"].get<float>(), t.coordinate(15, 0, 1));
  EXPECT_EQ(json["frames"][1]["difference"].get<double>(), 0.0);
  EXPECT_EQ(ProbePng(Scratch() / "frames" / "frame_15.png"), (std::pair<int, int>{640, 360}));
}

// frames -o EXISTING_DIR kept an earlier run's PNGs beside the new frames.json.
TEST(Render, FramesIntoAnEarlierRunsDirectoryHoldOnlyTheNewFrames) {
  const Trajectory t = OneParticle(15, 15, 15, 20);
  RenderOptions o;
  o.width = 64;
  o.height = 64;
  const fs::path out = Scratch() / "frames_rerun";
  fs::remove_all(out);
  RenderFrames(t, t, {0, 5, 15}, o, out);
  std::ofstream(out / "notes.txt") << "the user's";
  RenderFrames(t, t, {5}, o, out);
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(out)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"frame_5.png", "frames.json", "notes.txt"}));
}

// render -o DIR rendered every frame, then failed "cannot rename into place: Is a directory".
TEST(Render, VideoIntoAnExistingDirectoryIsRefusedBeforeRendering) {
  const Trajectory t = OneParticle(15, 15, 15, 4);
  RenderOptions o;
  o.width = 64;
  o.height = 64;
  const fs::path dir = Scratch() / "video_dir";
  fs::remove_all(dir);
  fs::create_directories(dir);
  try {
    RenderVideo(t, o, dir);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), dir.string() + ": is a directory; expected a file to write");
  }
  EXPECT_THROW(RenderSideBySide(t, t, o, dir), InputError);
  EXPECT_TRUE(fs::is_empty(dir));
}

// `frames --at ""` reached the gate with no frame and crashed after writing frames.json; 0,0,0
// wrote one PNG and three entries. Both are refused before any directory is created.
TEST(Render, FramesRefuseAnEmptyOrRepeatedListBeforeCreatingAnything) {
  const Trajectory t = OneParticle(15, 15, 15, 20);
  RenderOptions o;
  o.width = 64;
  o.height = 64;
  const fs::path out = Scratch() / "frames_refused";
  fs::remove_all(out);
  for (const std::vector<std::size_t>& frames :
       {std::vector<std::size_t>{}, {0, 0, 0}, {3, 5, 3}, {0, 15, 9999}}) {
    EXPECT_THROW(RenderFrames(t, t, frames, o, out), InputError);
    EXPECT_FALSE(fs::exists(out));
  }
}

}  // namespace
}  // namespace owval::render

namespace owval::render {
namespace {

TEST(Render, ConnectionsAreDrawnAsLinesWhenAsked) {
  Trajectory t;
  t.box = {0, 30, 0, 30, 0, 30};
  t.type = {2.1f, 2.1f};
  const float p[6] = {5, 15, 15, 25, 15, 15};
  t.AppendFrame(0, p);
  RenderOptions o;
  o.width = 320;
  o.height = 240;
  o.view = "front";
  const Camera camera = Camera::FromBox(t.box, o.view, float(o.width) / o.height);
  const auto mid = camera.Project({15, 15, 15}, o.width, o.height);
  auto green_at_mid = [&](const std::vector<unsigned char>& rgba) {
    const unsigned char* px = &rgba[(std::size_t(mid[1]) * o.width + std::size_t(mid[0])) * 4];
    return px[1] > px[0] + 40;
  };
  EXPECT_FALSE(green_at_mid(RenderFrameRgba(t, 0, o)));  // nothing between the two particles
  o.connections = {{0, 1}};
  EXPECT_TRUE(green_at_mid(RenderFrameRgba(t, 0, o)));
}

}  // namespace
}  // namespace owval::render
