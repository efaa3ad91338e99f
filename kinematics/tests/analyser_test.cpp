// The streaming Analyser (kinematics.hpp): the batch analysis' numbers bit for bit, with memory
// bounded by the speed windows' frames.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "owval/base/errors.hpp"
#include "owval/kinematics/kinematics.hpp"
#include "owval/kinematics/worm_track.hpp"
#include "owval/testing/scratch_directory.hpp"
#include "owval/trajectory/formats.hpp"
#include "owval/trajectory/frame_source.hpp"

namespace owval::kinematics {
namespace {
namespace fs = std::filesystem;

const fs::path kWormPositions =
    fs::path(OWVAL_SHARED_DIR) / "reference/worm_alone_0.6s/position_buffer.txt.gz";

// A travelling sine on a translating body, 49 points, at irregular frame times (40 fps on
// average, each step 0.5x-1.5x the mean), so that the speed windows close after varying numbers
// of frames.
SkeletonSeries Jittered(int frames) {
  SkeletonSeries s;
  double t = 0;
  for (int f = 0; f < frames; ++f) {
    Skeleton k;
    for (int i = 0; i <= 48; ++i) {
      const double x = 1.0 - i / 48.0;  // head first, at +x
      k.push_back({x + 0.2 * t, 0.05 * std::sin(2 * M_PI * (x / 0.6 + 1.7 * t))});
    }
    s.time_s.push_back(t);
    s.skeletons.push_back(k);
    t += 0.025 * (1 + 0.5 * std::sin(1.3 * f * f));
  }
  return s;
}

Point2 PartCentroid(const Skeleton& body, int first, int last) {
  Point2 c{0, 0};
  for (int i = first; i <= last; ++i) c = {c[0] + body[i][0], c[1] + body[i][1]};
  return {c[0] / (last - first + 1), c[1] / (last - first + 1)};
}

// The speed's definition over the whole series at once (the loop Analyse ran before it streamed):
// for each frame i the first frame j at t_i + w, signed by the head-tail direction at (i+j)/2.
std::optional<double> WholeSeriesSpeed(const SkeletonSeries& s, int first, int last,
                                       double window_s) {
  std::vector<Skeleton> body;
  for (const Skeleton& k : s.skeletons) body.push_back(ResampleByArcLength(k));
  double sum = 0;
  std::size_t used = 0;
  for (std::size_t i = 0, j = 0; i < body.size(); ++i) {
    while (j < body.size() && s.time_s[j] < s.time_s[i] + window_s - 1e-9) ++j;
    if (j >= body.size()) break;
    const Point2 a = PartCentroid(body[i], first, last), b = PartCentroid(body[j], first, last);
    const Point2 d{b[0] - a[0], b[1] - a[1]};
    const Point2 h = PartCentroid(body[(i + j) / 2], 0, 7),
                 t = PartCentroid(body[(i + j) / 2], 41, 48);
    const double speed = std::hypot(d[0], d[1]) / (s.time_s[j] - s.time_s[i]);
    sum += d[0] * (h[0] - t[0]) + d[1] * (h[1] - t[1]) < 0 ? -speed : speed;
    ++used;
  }
  if (used == 0) return std::nullopt;
  return sum / used;
}

TEST(Analyser, SpeedsEqualTheWholeSeriesLoopBitForBitAtIrregularFrameTimes) {
  const SkeletonSeries s = Jittered(400);
  const Report r = Analyse(s);
  ASSERT_TRUE(r.midbody_speed_mm_s && r.head_speed_mm_s && r.tail_speed_mm_s);
  EXPECT_EQ(*r.midbody_speed_mm_s, *WholeSeriesSpeed(s, 16, 32, 0.5));
  EXPECT_EQ(*r.head_speed_mm_s, *WholeSeriesSpeed(s, 0, 7, 0.25));
  EXPECT_EQ(*r.tail_speed_mm_s, *WholeSeriesSpeed(s, 41, 48, 0.25));
  EXPECT_NEAR(*r.midbody_speed_mm_s, 0.2, 0.02);  // the body's translation
}

// A run shorter than the midbody window closes none: no speed, as the whole-series loop.
TEST(Analyser, NoSpeedWhenNoWindowCloses) {
  const SkeletonSeries s = Jittered(12);  // about 0.3 s
  const Report r = Analyse(s);
  EXPECT_FALSE(r.midbody_speed_mm_s);
  EXPECT_EQ(r.head_speed_mm_s.has_value(), WholeSeriesSpeed(s, 0, 7, 0.25).has_value());
}

// Memory: the frames held for the speeds stay those of the longest window (0.5 s, at most ~1.5x
// 20 frames of the jittered 40 fps) however long the run; a run held whole would grow with it.
TEST(Analyser, HoldsTheSpeedWindowsFramesNotTheRuns) {
  const SkeletonSeries s = Jittered(1500);  // ~37 s
  Analyser a;
  std::size_t most = 0;
  for (std::size_t f = 0; f < s.time_s.size(); ++f) {
    a.Observe(s.time_s[f], s.skeletons[f]);
    most = std::max(most, a.window_frames());
  }
  EXPECT_LE(most, 42u);
  EXPECT_GE(most, 10u);
  EXPECT_EQ(a.frames(), 1500u);
  std::printf("most frames held for the speed windows: %zu of 1500\n", most);
}

// Sibernetic's 0.6 s worm run: the report of the batch analysis (Analyse over the whole
// skeleton series, owval at c17facb, `owval kinematics position_buffer.txt.gz --json`), which
// the streaming analysis must give bit for bit (JSON doubles round-trip exactly).
TEST(Analyser, WormReferenceGivesTheBatchAnalysisReportBitForBit) {
  if (!fs::exists(kWormPositions)) GTEST_SKIP() << "no " << kWormPositions;
  const nlohmann::json batch = nlohmann::json::parse(R"({
    "amplitude_mm": 0.10111925460583347, "duration_s": 0.5970000000000001,
    "fft_frequency_hz": 2.0123392922358967, "frames": 200, "frequency_hz": null,
    "frequency_note": "fewer than 3 zero crossings of the bend angle",
    "head_speed_mm_per_s": -0.29944273384594766, "length_mm": 1.1150279917510004,
    "max_amplitude_mm": 0.1892184839186127, "midbody_speed_mm_per_s": 0.08321880813099593,
    "regime": "crawling", "tail_speed_mm_per_s": 0.003917603078329838,
    "wavelength_mm": 0.8039366670070642, "zero_crossing_frequency_hz": null})");
  EXPECT_EQ(AnalyseFile(kWormPositions).ToJson(), batch);
  EXPECT_EQ(Analyse(LoadSkeletons(kWormPositions)).ToJson(), batch);
  TextReadOptions quiet;
  quiet.quiet = true;
  EXPECT_EQ(AnalyseFrames(*OpenFrameSource(kWormPositions, quiet)).ToJson(), batch);
}

TEST(Analyser, RefusesWhatAnalyseRefusedAtFinish) {
  const SkeletonSeries s = Jittered(3);
  Analyser one;
  one.Observe(s.time_s[0], s.skeletons[0]);
  EXPECT_THROW(
      {
        try {
          one.Finish();
        } catch (const InputError& e) {
          EXPECT_STREQ(e.what(), "kinematics need at least 2 frames with one skeleton each");
          throw;
        }
      },
      InputError);
  Analyser short_skeleton;
  short_skeleton.Observe(0, s.skeletons[0]);
  short_skeleton.Observe(0.1, {{0, 0}});
  short_skeleton.Observe(0.2, s.skeletons[2]);
  EXPECT_THROW(
      {
        try {
          short_skeleton.Finish();
        } catch (const InputError& e) {
          EXPECT_STREQ(e.what(), "skeleton needs at least 2 points");
          throw;
        }
      },
      InputError);
}

// `owval kinematics` reads through AnalyseFile: LoadSkeletons' refusals, naming the file.
TEST(Analyser, AnalyseFileRefusesTooFewFramesOrPointsNamingTheFile) {
  const fs::path dir = owval::testing::TestScratch("analyser");
  const fs::path file = dir / "too_little.wcon";
  auto message = [&](const std::string& t, const std::string& x) -> std::string {
    std::ofstream(file) << R"({"units": {"t": "s", "x": "mm", "y": "mm"}, "data": {"id": "1", )"
                        << "\"t\": " << t << ", \"x\": " << x << ", \"y\": " << x << "}}";
    try {
      AnalyseFile(file);
    } catch (const InputError& e) {
      return e.what();
    }
    return "accepted";
  };
  EXPECT_EQ(message("[0]", "[[0, 1]]"),
            file.string() + ": holds 1 frame(s): kinematics need at least 2 frames");
  EXPECT_EQ(message("[0, 1, 2]", "[[0, 1], [2], [3]]"),
            file.string() +
                ": frame 1's skeleton has 1 point(s): kinematics need at least 2 midline points a "
                "frame");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace owval::kinematics
