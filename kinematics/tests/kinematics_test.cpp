#include "owval/kinematics/kinematics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace owval::kinematics {
namespace {

struct Wave {
  double speed_mm_s = 0;    // translation along +x (the head end)
  double frequency_hz = 0;  // undulation
  double wavelength_mm = 0.5;
  double amplitude_mm = 0;
  double body_x_mm = 1.0;  // extent of the body along x
  double duration_s = 5;
  double fps = 40;
  double second_frequency_hz = 0;  // a second wave of the same amplitude and wavelength
};

// A sine wave travelling from head (+x end) to tail along a body that translates along +x:
// y = A sin(2 pi (x / lambda + f t)), sampled densely (401 points) at every frame.
SkeletonSeries Synthetic(const Wave& w) {
  SkeletonSeries s;
  const int frames = static_cast<int>(std::lround(w.duration_s * w.fps)) + 1;
  for (int f = 0; f < frames; ++f) {
    const double t = f / w.fps;
    Skeleton k;
    for (int i = 0; i <= 400; ++i) {
      const double x = w.body_x_mm * (1 - i / 400.0);  // head first
      double y = w.amplitude_mm * std::sin(2 * M_PI * (x / w.wavelength_mm + w.frequency_hz * t));
      if (w.second_frequency_hz > 0)
        y += w.amplitude_mm *
             std::sin(2 * M_PI * (x / w.wavelength_mm + w.second_frequency_hz * t) + 1.0);
      k.push_back({x + w.speed_mm_s * t, y});
    }
    s.time_s.push_back(t);
    s.skeletons.push_back(k);
  }
  return s;
}

void ExpectWithin(double measured, double truth, double relative, const char* what) {
  EXPECT_NEAR(measured, truth, relative * std::abs(truth)) << what;
  std::printf("%-24s %.6g (truth %.6g, %+.3f%%)\n", what, measured, truth,
              100 * (measured - truth) / truth);
}

// At 4 Hz the speed windows (0.25 s, 0.5 s) span whole periods, so the undulation's lateral
// excursion cancels and the windowed displacement is the translation alone.
TEST(Kinematics, SwimmingSineRecoversSpeedFrequencyWavelengthAmplitudeWithin2Percent) {
  Wave w{.speed_mm_s = 0.3, .frequency_hz = 4, .wavelength_mm = 0.5, .amplitude_mm = 0.05};
  const Report r = Analyse(Synthetic(w));
  ASSERT_TRUE(r.midbody_speed_mm_s && r.head_speed_mm_s && r.tail_speed_mm_s);
  ExpectWithin(*r.midbody_speed_mm_s, 0.3, 0.02, "midbody speed");
  ExpectWithin(*r.head_speed_mm_s, 0.3, 0.02, "head speed");
  ExpectWithin(*r.tail_speed_mm_s, 0.3, 0.02, "tail speed");
  ASSERT_TRUE(r.frequency_hz) << r.frequency_note;
  ExpectWithin(*r.frequency_hz, 4, 0.02, "frequency");
  ExpectWithin(*r.zero_crossing_frequency_hz, 4, 0.02, "zero-crossing frequency");
  ASSERT_TRUE(r.wavelength_mm && r.amplitude_mm && r.max_amplitude_mm);
  ExpectWithin(*r.wavelength_mm, 0.5, 0.02, "wavelength");
  ExpectWithin(*r.amplitude_mm, 0.05, 0.02, "amplitude");
  ExpectWithin(*r.max_amplitude_mm, 0.05, 0.02, "max amplitude");
  EXPECT_EQ(r.regime, Regime::kSwimming);
}

TEST(Kinematics, CrawlingSineRecoversFrequencyWavelengthAmplitudeWithin2Percent) {
  Wave w{.speed_mm_s = 0.14,
         .frequency_hz = 0.37,
         .wavelength_mm = 0.67,
         .amplitude_mm = 0.04,
         .body_x_mm = 1.0,
         .duration_s = 12,
         .fps = 30};
  const Report r = Analyse(Synthetic(w));
  ASSERT_TRUE(r.frequency_hz) << r.frequency_note;
  ExpectWithin(*r.frequency_hz, 0.37, 0.02, "frequency");
  ASSERT_TRUE(r.wavelength_mm && r.amplitude_mm);
  ExpectWithin(*r.wavelength_mm, 0.67, 0.02, "wavelength");
  ExpectWithin(*r.amplitude_mm, 0.04, 0.02, "amplitude");
  EXPECT_EQ(r.regime, Regime::kCrawling);
}

TEST(Kinematics, BackwardMotionHasNegativeSpeed) {
  Wave w{.speed_mm_s = -0.2, .frequency_hz = 4, .wavelength_mm = 0.5, .amplitude_mm = 0.05};
  const Report r = Analyse(Synthetic(w));
  ASSERT_TRUE(r.midbody_speed_mm_s);
  ExpectWithin(*r.midbody_speed_mm_s, -0.2, 0.02, "midbody speed");
}

TEST(Kinematics, StraightStillBodyHasZeroSpeedAndNoFrequency) {
  const Report r = Analyse(Synthetic(Wave{}));
  ASSERT_TRUE(r.midbody_speed_mm_s && r.head_speed_mm_s);
  EXPECT_EQ(*r.midbody_speed_mm_s, 0.0);
  EXPECT_EQ(*r.head_speed_mm_s, 0.0);
  EXPECT_FALSE(r.frequency_hz);
  EXPECT_FALSE(r.fft_frequency_hz);
  EXPECT_FALSE(r.wavelength_mm);
  EXPECT_EQ(r.frequency_note, "midbody does not bend");
  EXPECT_NEAR(r.length_mm, 1.0, 1e-12);
}

TEST(Kinematics, LessThanOneCycleGivesNoFrequency) {
  Wave w{.frequency_hz = 0.5, .amplitude_mm = 0.05, .duration_s = 1.2};
  const Report r = Analyse(Synthetic(w));
  EXPECT_FALSE(r.frequency_hz);
  EXPECT_NE(r.frequency_note.find("less than one cycle"), std::string::npos) << r.frequency_note;
}

// Two undulations of equal strength: the larger spectral peak holds about half the energy and its
// neighbour's trough is shallow, so the toolbox's rules reject it.
TEST(Kinematics, TwoEqualUndulationsGiveNoFrequency) {
  Wave w{.frequency_hz = 0.9,
         .amplitude_mm = 0.03,
         .duration_s = 10,
         .fps = 30,
         .second_frequency_hz = 1.3};
  const Report r = Analyse(Synthetic(w));
  EXPECT_FALSE(r.frequency_hz) << *r.frequency_hz << " zc " << *r.zero_crossing_frequency_hz;
  EXPECT_TRUE(r.frequency_note.find("peak weak") != std::string::npos ||
              r.frequency_note.find("peak unclear") != std::string::npos)
      << r.frequency_note;
}

TEST(Kinematics, RunShorterThanTheSpeedWindowHasNoSpeed) {
  Wave w{.duration_s = 0.3};
  const Report r = Analyse(Synthetic(w));
  EXPECT_FALSE(r.midbody_speed_mm_s);
  EXPECT_TRUE(r.head_speed_mm_s);
}

TEST(Kinematics, ResamplingGives49PointsEvenlyAlongTheArc) {
  const Skeleton s = ResampleByArcLength({{0, 0}, {1, 0}, {1, 3}});
  ASSERT_EQ(s.size(), 49u);
  EXPECT_DOUBLE_EQ(s[12][0], 1.0);  // a quarter of 4 units: the corner
  EXPECT_DOUBLE_EQ(s[12][1], 0.0);
  EXPECT_DOUBLE_EQ(s[48][1], 3.0);
  EXPECT_NEAR(ArcLength(s), 4.0, 1e-12);
}

}  // namespace
}  // namespace owval::kinematics
