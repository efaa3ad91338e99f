#include "owval/compare/parity.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>
#include <numbers>
#include <vector>

#include "owval/base/errors.hpp"
#include "owval/compare/stability.hpp"
#include "owval/testing/reference_runs.hpp"
#include "owval/trajectory/formats.hpp"
#include "owval/trajectory/frame_source.hpp"

namespace owval::compare {
namespace {

TEST(Parity, ReferenceAgainstItselfPassesWithZeroError) {
  const ParityReport r =
      CompareTrajectories(testing::BundledOneSprigRun(), testing::BundledOneSprigRun(), {});
  EXPECT_TRUE(r.pass());
  EXPECT_EQ(r.paired_frames, 2500u);
  EXPECT_EQ(r.l2_mean_cu, 0.0);
  for (const FrameParity& f : r.frames) EXPECT_EQ(f.relative_difference, 0.0);
  EXPECT_EQ(*r.period_gap, 0.0);
}

TEST(Parity, ElasticYScaledBy106FailsTheFrameGateAndNamesFrames) {
  Trajectory scaled = testing::BundledOneSprigRun();
  for (std::size_t f = 0; f < scaled.frame_count(); ++f) scaled.position(f, 0)[1] *= 1.06f;
  ParityOptions options;
  options.sample_frames = {0, 15, 100, 200};
  const ParityReport r = CompareTrajectories(testing::BundledOneSprigRun(), scaled, options);
  EXPECT_EQ(r.gate("frames")->status, GateStatus::kFail);
  EXPECT_FALSE(r.pass());
  // The amplitude scales by 6% too, and the scaled run starts elsewhere (initial_state).
  EXPECT_EQ(r.FailedGates(), "initial_state, frames, frames.position, half_amplitude");
  EXPECT_EQ(r.failing_frames, (std::vector<std::size_t>{0, 15, 100, 200}));
  // 6% of y ≈ 18 is ≈ 1.1 cu against a 3.39 cu range: about a third of the scale.
  EXPECT_NEAR(r.frames[0].relative_difference, 0.06 * 20.04 / 3.388, 1e-3);
  EXPECT_NE(r.ToMarkdown().find("failing frames 0, 15, 100, 200"), std::string::npos);
  EXPECT_NE(
      r.ToTable().find("FAIL (failed: initial_state, frames, frames.position, half_amplitude)"),
      std::string::npos);
}

// The checklist's item 5 and `owval frames` take the sample frames' gates from this lighter
// reduction: it must give the whole report's two gates and failing frames, bit for bit.
void ExpectSampledFramesAsTheWholeReport(const Trajectory& reference, const Trajectory& candidate,
                                         const ParityOptions& options) {
  const ParityReport whole = CompareTrajectories(reference, candidate, options);
  const auto refs = MemoryFrameSource(reference), cands = MemoryFrameSource(candidate);
  const SampledFrameParity sampled = CompareSampledFrames(*refs, *cands, options);
  EXPECT_EQ(ToJson(sampled.frames), ToJson(*whole.gate("frames")));
  ASSERT_TRUE(sampled.group_centroids.has_value());
  EXPECT_EQ(ToJson(*sampled.group_centroids), ToJson(*whole.gate("frames.group_centroids")));
  EXPECT_EQ(sampled.failing_frames, whole.failing_frames);
}

TEST(SampledFrames, GivesTheWholeReportsGatesAtTheSampleFrames) {
  ParityOptions options;
  options.sample_frames = {0, 15, 100, 200, 2499};
  ExpectSampledFramesAsTheWholeReport(testing::BundledOneSprigRun(), testing::BundledOneSprigRun(),
                                      options);
  // particle 0 y 6% higher, the elastic centroid with it
  Trajectory moved = testing::BundledOneSprigRun();
  for (std::size_t f = 0; f < moved.frame_count(); ++f) moved.position(f, 0)[1] *= 1.06f;
  options.sample_frames = {0, 15, 100, 200};
  ExpectSampledFramesAsTheWholeReport(testing::BundledOneSprigRun(), moved, options);
  options.gates.centroid_distance = {1e-4, ThresholdSource::kFlag};  // and the centroids' gate
  ExpectSampledFramesAsTheWholeReport(testing::BundledOneSprigRun(), moved, options);
  const ParityReport whole = CompareTrajectories(testing::BundledOneSprigRun(), moved, options);
  EXPECT_EQ(whole.gate("frames")->status, GateStatus::kFail);
  EXPECT_EQ(whole.gate("frames.group_centroids")->status, GateStatus::kFail);
}

TEST(Parity, PairsFramesByTimeAcrossLogSteps) {
  Trajectory coarse = testing::BundledOneSprigRun();
  // Keep every 10th frame: a candidate logged with log step 10.
  Trajectory thinned;
  thinned.box = coarse.box;
  thinned.type = coarse.type;
  thinned.time_step_s = coarse.time_step_s;
  thinned.log_step = 10;
  for (std::size_t f = 0; f < coarse.frame_count(); f += 10)
    thinned.AppendFrame(coarse.time_s[f], coarse.position(f, 0));
  const auto pairs = PairFramesByTime(coarse, thinned);
  ASSERT_EQ(pairs.size(), 250u);
  EXPECT_EQ(pairs[3], (std::pair<std::size_t, std::size_t>{30, 3}));
  EXPECT_TRUE(CompareTrajectories(coarse, thinned, {}).pass());
}

TEST(Parity, RefusesDifferentParticleCounts) {
  Trajectory fewer = testing::BundledOneSprigRun();
  fewer.type.pop_back();
  Trajectory rebuilt;
  rebuilt.type = fewer.type;
  rebuilt.box = fewer.box;
  std::vector<float> frame(fewer.type.size() * 3, 1.0f);
  rebuilt.AppendFrame(0, frame.data());
  EXPECT_THROW(CompareTrajectories(testing::BundledOneSprigRun(), rebuilt, {}), InputError);
}

// The first `frames` frames of a trajectory: the same run recorded for a shorter time.
Trajectory FirstFrames(const Trajectory& t, std::size_t frames) {
  Trajectory out;
  out.box = t.box;
  out.type = t.type;
  out.time_step_s = t.time_step_s;
  out.log_step = t.log_step;
  for (std::size_t f = 0; f < frames; ++f) out.AppendFrame(t.time_s[f], t.position(f, 0));
  return out;
}

TEST(Parity, IdenticalRunsOfDifferentDurationsAgreeOverTheCommonWindow) {
  // 250 of 2500 frames (5 ms of 50 ms, about 7 periods): every measure on both sides is taken
  // over those 5 ms, so nothing differs; but the shorter candidate covers a tenth of the
  // reference, which the window gate fails unless the caller accepts it.
  const Trajectory shorter = FirstFrames(testing::BundledOneSprigRun(), 250);
  ParityOptions over_the_common_window;
  over_the_common_window.gates.window = {1.0, ThresholdSource::kFlag};
  for (const ParityOptions& o : {ParityOptions{}, over_the_common_window}) {
    const ParityReport r = CompareTrajectories(testing::BundledOneSprigRun(), shorter, o);
    EXPECT_EQ(r.paired_frames, 250u);
    EXPECT_EQ(*r.half_amplitude_gap, 0.0);
    EXPECT_EQ(r.gate("period")->status, GateStatus::kPass);
    EXPECT_NEAR(r.gate("window")->value, 0.9, 0.001);
  }
  const ParityReport strict = CompareTrajectories(testing::BundledOneSprigRun(), shorter, {});
  EXPECT_FALSE(strict.pass());
  EXPECT_EQ(strict.FailedGates(), "window") << strict.ToTable();
  EXPECT_TRUE(
      CompareTrajectories(testing::BundledOneSprigRun(), shorter, over_the_common_window).pass());
  // A candidate longer than the reference covers it.
  const ParityReport longer = CompareTrajectories(shorter, testing::BundledOneSprigRun(), {});
  EXPECT_TRUE(longer.pass()) << longer.ToTable();
  EXPECT_EQ(longer.gate("window")->value, 0.0);
}

TEST(Parity, ACandidateOfOneFrameFailsTheWindowGate) {
  const ParityReport r = CompareTrajectories(testing::BundledOneSprigRun(),
                                             FirstFrames(testing::BundledOneSprigRun(), 1), {});
  EXPECT_FALSE(r.pass()) << r.ToTable();
  EXPECT_EQ(r.gate("window")->status, GateStatus::kFail);
  EXPECT_EQ(r.gate("window")->value, 1.0);
}

TEST(Parity, AnInterruptedRunIsComparedOverItsFramesAndTheReportSaysSo) {
  Trajectory interrupted = FirstFrames(testing::BundledOneSprigRun(), 250);
  interrupted.provenance["partial"] = "interrupted after step 2500";
  const ParityReport r = CompareTrajectories(testing::BundledOneSprigRun(), interrupted, {});
  EXPECT_FALSE(r.reference_partial);
  EXPECT_TRUE(r.candidate_partial);
  EXPECT_EQ(r.ToJson()["candidate_partial"], true);
  EXPECT_NE(r.ToTable().find("note: the candidate is partial"), std::string::npos);
  EXPECT_EQ(r.ToTable().find("the reference is partial"), std::string::npos);
  EXPECT_FALSE(CompareTrajectories(testing::BundledOneSprigRun(), testing::BundledOneSprigRun(), {})
                   .candidate_partial);
}

TEST(Parity, OscillationGatesDoNotApplyWithoutEnoughCrossings) {
  // 30 frames (0.6 ms) hold less than one period: one upward crossing at most.
  const Trajectory short_run = FirstFrames(testing::BundledOneSprigRun(), 30);
  Trajectory shifted = short_run;
  for (std::size_t f = 0; f < shifted.frame_count(); ++f) shifted.position(f, 0)[1] += 0.01f;
  const ParityReport r = CompareTrajectories(short_run, shifted, {});
  EXPECT_EQ(r.gate("period")->status, GateStatus::kNotApplicable);
  EXPECT_EQ(r.gate("half_amplitude")->status, GateStatus::kNotApplicable);
  EXPECT_NE(r.gate("period")->detail.find("need >= 4"), std::string::npos);
  // The frame gate still judges: 0.01 cu against the short run's range.
  EXPECT_NE(r.gate("frames")->status, GateStatus::kNotApplicable);
}

TEST(Parity, OscillationGatesApplyAndFailOnAStifferSpring) {
  // A candidate whose period is 5% shorter: the signal resampled at 1.05x the time.
  Trajectory faster = testing::BundledOneSprigRun();
  const Trajectory& ref = testing::BundledOneSprigRun();
  for (std::size_t f = 0; f < faster.frame_count(); ++f) {
    const std::size_t g = std::min(ref.frame_count() - 1, std::size_t(double(f) * 1.05));
    faster.position(f, 0)[1] = ref.position(g, 0)[1];
  }
  const ParityReport r = CompareTrajectories(ref, faster, {});
  EXPECT_EQ(r.gate("period")->status, GateStatus::kFail);
  EXPECT_NE(r.FailedGates().find("period"), std::string::npos);
}

// A candidate logged at two instants only: a 5% stiffer spring (the reference resampled at 1.05x
// the time) whose first frame and the frame near the end where it happens to be back in phase
// were kept. Every gate that reads the paired frames agrees; the sampling gate and the
// oscillation gates (the reference oscillates over its own frames) must not.
TEST(Parity, ACandidateLoggedAtTwoWellChosenInstantsFails) {
  const Trajectory& ref = testing::BundledOneSprigRun();
  const std::size_t frames = ref.frame_count();
  auto faster_y = [&](std::size_t f) {
    return ref.position(std::min(frames - 1, std::size_t(double(f) * 1.05)), 0)[1];
  };
  std::size_t in_phase = frames - 50;  // within the window gate's 2% of the end
  for (std::size_t f = frames - 50; f < frames; ++f)
    if (std::abs(faster_y(f) - ref.position(f, 0)[1]) <
        std::abs(faster_y(in_phase) - ref.position(in_phase, 0)[1]))
      in_phase = f;
  Trajectory sparse = FirstFrames(ref, 1);
  sparse.log_step = int(in_phase);
  std::vector<float> last(ref.position(in_phase, 0),
                          ref.position(in_phase, 0) + 3 * ref.particle_count());
  last[1] = faster_y(in_phase);
  sparse.AppendFrame(ref.time_s[in_phase], last.data());
  const ParityReport r = CompareTrajectories(ref, sparse, {});
  EXPECT_EQ(r.gate("frames")->status, GateStatus::kPass) << r.ToTable();
  EXPECT_EQ(r.gate("window")->status, GateStatus::kPass);
  EXPECT_FALSE(r.pass());
  EXPECT_EQ(r.FailedGates(), "sampling, sampling.oscillation, period, half_amplitude");
  EXPECT_GT(r.gate("sampling")->value, 0.95);
  EXPECT_GE(r.reference_crossings_all_frames, 60u);
  EXPECT_NE(r.gate("period")->detail.find("do not resolve it"), std::string::npos);
}

TEST(Parity, ACandidateThatStopsOscillatingFailsTheOscillationGates) {
  // Dense frames, but the candidate holds the spring still at its mean: no crossings of its own.
  Trajectory still = testing::BundledOneSprigRun();
  double mean = 0;
  for (std::size_t f = 0; f < still.frame_count(); ++f) mean += still.position(f, 0)[1];
  mean /= double(still.frame_count());
  for (std::size_t f = 0; f < still.frame_count(); ++f) still.position(f, 0)[1] = float(mean);
  ParityOptions loose;  // a frame gate loose enough to let the still spring through
  loose.gates.frame = {1.0, ThresholdSource::kFlag};
  loose.gates.centroid_distance = loose.gates.final_distance =
      loose.gates.particle_distance = {1.0, ThresholdSource::kFlag};
  const ParityReport r = CompareTrajectories(testing::BundledOneSprigRun(), still, loose);
  EXPECT_EQ(r.gate("period")->status, GateStatus::kFail) << r.ToTable();
  EXPECT_EQ(r.gate("sampling")->status, GateStatus::kPass);
  EXPECT_EQ(r.gate("sampling")->value, 0.0);
}

// --scale replaces the reference's range as the frame gate's denominator: a large one loosens the
// gate as a large threshold would, so the report says the scale was given and what it replaced.
TEST(Parity, AGivenScaleIsReportedAsGiven) {
  Trajectory scaled = testing::BundledOneSprigRun();
  for (std::size_t f = 0; f < scaled.frame_count(); ++f) scaled.position(f, 0)[1] *= 1.06f;
  ParityOptions loose;
  loose.scale = 1000.0;
  const ParityReport r = CompareTrajectories(testing::BundledOneSprigRun(), scaled, loose);
  EXPECT_EQ(r.gate("frames")->status, GateStatus::kPass);
  EXPECT_TRUE(r.scale_given);
  EXPECT_NEAR(r.reference_range, 3.388, 1e-3);
  EXPECT_EQ(r.gate("frames")->unit, "of the given scale");
  EXPECT_NE(r.gate("frames")->detail.find("given by the caller (--scale)"), std::string::npos);
  EXPECT_NE(r.ToMarkdown().find("GIVEN by the caller"), std::string::npos) << r.ToMarkdown();
  EXPECT_EQ(r.ToMarkdown().find("(reference range)"), std::string::npos);
  EXPECT_NE(r.ToTable().find("GIVEN by --scale"), std::string::npos);
  EXPECT_EQ(r.ToJson()["scale_given"], true);
  EXPECT_FALSE(CompareTrajectories(testing::BundledOneSprigRun(), scaled, {}).scale_given);
}

TEST(Parity, FinalStateGateNamesAnOffsetAtTheEnd) {
  Trajectory moved = testing::BundledOneSprigRun();
  const std::size_t last = moved.frame_count() - 1;
  moved.position(last, 0)[0] += 5.0f;  // 5 cu of a 33.4 cu box: 15%
  const ParityReport r = CompareTrajectories(testing::BundledOneSprigRun(), moved, {});
  EXPECT_EQ(r.gate("frames")->status, GateStatus::kPass);  // y is untouched
  EXPECT_EQ(r.gate("elastic.final_distance")->status, GateStatus::kFail);
  EXPECT_NEAR(r.gate("elastic.final_distance")->value, 5.0 / 33.4, 1e-3);
  EXPECT_NE(r.FailedGates().find("elastic.final_distance"), std::string::npos);
  EXPECT_FALSE(r.pass());
}

// The gates added since the table's first rows are settable as the others: a manifest key and a
// flag, each naming its own ParityGates member.
TEST(GateThresholdFields, NewGatesHaveAManifestKeyAndAFlag) {
  struct Expected {
    const char* manifest_key;
    const char* flag;
    Threshold ParityGates::*member;
  };
  for (const Expected& e :
       {Expected{"worst_particle_threshold", "--worst-particle-threshold",
                 &ParityGates::worst_particle},
        Expected{"initial_state_threshold", "--initial-state-threshold",
                 &ParityGates::initial_state},
        Expected{"closest_approach_threshold", "--closest-approach-threshold",
                 &ParityGates::closest_approach},
        Expected{"held_pair_threshold", "--held-pair-threshold", &ParityGates::held_pair}}) {
    const auto field = std::find_if(
        kGateThresholdFields.begin(), kGateThresholdFields.end(),
        [&](const GateThresholdField& f) { return std::string(f.manifest_key) == e.manifest_key; });
    ASSERT_NE(field, kGateThresholdFields.end()) << e.manifest_key;
    EXPECT_STREQ(field->flag, e.flag);
    EXPECT_EQ(field->member, e.member);
  }
}

TEST(Parity, ThresholdsCarryTheirSource) {
  ParityOptions options;
  options.gates.frame = {0.5, ThresholdSource::kFlag};
  Trajectory scaled = testing::BundledOneSprigRun();
  for (std::size_t f = 0; f < scaled.frame_count(); ++f) scaled.position(f, 0)[1] *= 1.06f;
  const ParityReport r = CompareTrajectories(testing::BundledOneSprigRun(), scaled, options);
  EXPECT_EQ(r.gate("frames")->status, GateStatus::kPass);  // 0.35 < 0.5
  EXPECT_EQ(r.gate("frames")->threshold.source, ThresholdSource::kFlag);
  EXPECT_EQ(ToJson(*r.gate("frames"))["threshold_source"], "flag");
  EXPECT_EQ(r.gate("extent"), nullptr);
  EXPECT_EQ(r.gate("elastic.extent")->threshold.source, ThresholdSource::kDefault);
}

// A 3 × 3 × 3 elastic lattice (spacing 2 cu) in a 20 cu box, at its first frame and then
// turned about the vertical by `turn_deg` and stretched along its own x by `stretch`.
Trajectory TurnedLattice(double turn_deg, double stretch) {
  Trajectory t;
  t.box = {0, 20, 0, 20, 0, 20};
  t.time_step_s = 1e-3;
  std::vector<float> first, last;
  const double c = std::cos(turn_deg * std::numbers::pi / 180),
               s = std::sin(turn_deg * std::numbers::pi / 180);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) {
        t.type.push_back(2.1f);
        const double x = 2.0 * (i - 1), y = 2.0 * (j - 1), z = 2.0 * (k - 1);
        first.insert(first.end(), {float(10 + x), float(10 + y), float(10 + z)});
        const double xs = stretch * x;  // body frame: stretched along x, then turned about y
        last.insert(last.end(),
                    {float(10 + c * xs + s * z), float(10 + y), float(10 - s * xs + c * z)});
      }
  t.AppendFrame(0, first.data());
  t.AppendFrame(1e-3, last.data());
  return t;
}

TEST(Parity, ExtentGateSaysHowFarEachBodyTurnedAndItsOwnExtents) {
  // The candidate's cube turns 30° about y where the reference's holds still: its bounding box
  // grows in x and z (the gate fails) but its shape in its own axes is the reference's.
  const ParityReport turned = CompareTrajectories(TurnedLattice(0, 1), TurnedLattice(30, 1), {});
  ASSERT_EQ(turned.drift.size(), 1u);
  const GroupDrift& d = turned.drift[0];
  EXPECT_TRUE(d.has_pose);
  EXPECT_NEAR(d.final_rotation_deg[0], 0.0, 1e-3);
  EXPECT_NEAR(d.final_rotation_deg[1], 30.0, 1e-3);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(d.final_body_extent_ratio[a], 1.0, 1e-5);
  EXPECT_NEAR(d.final_extent_ratio[0],
              std::cos(std::numbers::pi / 6) + std::sin(std::numbers::pi / 6), 1e-5);
  EXPECT_EQ(turned.gate("elastic.extent")->status, GateStatus::kFail);
  EXPECT_NE(turned.gate("elastic.extent")->detail.find("turned 0.0 deg (reference) and 30.0 deg"),
            std::string::npos);
  // Stretched 20% along its own x as well: the body extents say so.
  const ParityReport stretched =
      CompareTrajectories(TurnedLattice(0, 1), TurnedLattice(30, 1.2), {});
  EXPECT_NEAR(stretched.drift[0].final_body_extent_ratio[0], 1.2, 1e-5);
  EXPECT_NEAR(stretched.drift[0].final_body_extent_ratio[1], 1.0, 1e-5);
  EXPECT_NEAR(stretched.drift[0].final_body_extent_ratio[2], 1.0, 1e-5);
  EXPECT_EQ(stretched.ToJson()["group_drift"][0]["final_rotation_deg"]["candidate"].get<double>(),
            stretched.drift[0].final_rotation_deg[1]);
}

TEST(Parity, ABlownUpBodyHasNoTurn) {
  Trajectory blown = TurnedLattice(30, 1);
  blown.position(1, 4)[0] = std::numeric_limits<float>::quiet_NaN();
  const ParityReport r = CompareTrajectories(TurnedLattice(0, 1), blown, {});
  EXPECT_TRUE(std::isnan(r.drift[0].final_rotation_deg[1]));
  EXPECT_TRUE(std::isnan(r.drift[0].final_body_extent_ratio[0]));
  EXPECT_EQ(r.drift[0].final_rotation_deg[0], 0.0);
  EXPECT_FALSE(r.pass());
}

TEST(Parity, AOneParticleBodyHasNoTurn) {
  const ParityReport r =
      CompareTrajectories(testing::BundledOneSprigRun(), testing::BundledOneSprigRun(), {});
  EXPECT_FALSE(r.drift[0].has_pose);
  EXPECT_EQ(r.gate("elastic.extent")->detail.find("turned"), std::string::npos);
  EXPECT_TRUE(r.ToJson()["group_drift"][0]["final_rotation_deg"].is_null());
}

TEST(Parity, RefusesATrackThatNamesNothing) {
  ParityOptions options;
  options.track.particle = 99999999;
  EXPECT_THROW(
      CompareTrajectories(testing::BundledOneSprigRun(), testing::BundledOneSprigRun(), options),
      InputError);
}

Trajectory TwoLiquidParticles(std::size_t frames) {
  Trajectory t;
  t.box = {0, 10, 0, 10, 0, 10};
  t.time_step_s = 1e-3;
  t.type = {1.1f, 1.1f};
  for (std::size_t f = 0; f < frames; ++f) {
    const float x[6] = {5, 5, 5, 6, 5, 5};
    t.AppendFrame(double(f) * 1e-3, x);
  }
  t.velocities.assign(frames * 6, 0.0f);
  t.density.assign(frames * 2, 1000.0f);
  return t;
}

TEST(Stability, CleanTrajectoryPasses) {
  EXPECT_TRUE(CheckStability(TwoLiquidParticles(5)).pass());
}

TEST(Stability, FindsNaNEscapesBlowUpAndDensityWithFirstFrames) {
  Trajectory t = TwoLiquidParticles(10);
  t.position(3, 0)[1] = std::numeric_limits<float>::quiet_NaN();
  t.position(5, 1)[0] = 12.5f;  // 2.5 cu outside, tolerance 1
  t.velocities[(7 * 2 + 0) * 3] = 50.0f;
  t.velocities[(7 * 2 + 1) * 3] = 50.0f;
  t.density[8 * 2 + 1] = 9000.0f;
  const StabilityReport r = CheckStability(t);
  EXPECT_FALSE(r.pass());
  EXPECT_EQ(r.non_finite.count, 1u);
  EXPECT_EQ(*r.non_finite.first_frame, 3u);
  EXPECT_EQ(r.outside_box.count, 1u);
  EXPECT_EQ(*r.outside_box.first_frame, 5u);
  EXPECT_EQ(r.blow_up.count, 1u);
  EXPECT_EQ(*r.blow_up.first_frame, 7u);
  EXPECT_EQ(*r.density_out_of_range.first_frame, 8u);
}

TEST(Stability, BlowUpFromPositionsWhenNoVelocities) {
  Trajectory t = TwoLiquidParticles(4);
  t.velocities.clear();
  t.position(2, 0)[0] = 9.9f;  // 4.9 cu in 1 ms = 0.036 m/s: fine
  EXPECT_TRUE(CheckStability(t).pass());
  StabilityOptions strict;
  strict.speed_limit_m_s = 0.01;
  EXPECT_EQ(CheckStability(t, strict).blow_up.first_frame, 2u);
}

// The long-run gate's density rule: liquid only, a frame fails when more than 1% of the liquid
// particles leave 700-1300 kg/m^3; fed frame by frame, memory O(particles).
TEST(StabilityMonitor, LiquidDensityRuleToleratesOnePercentAndIgnoresOtherKinds) {
  Trajectory t;
  t.box = {0, 100, 0, 100, 0, 100};
  t.type.assign(200, 1.1f);  // 200 liquid particles, then an elastic and a boundary one
  t.type.push_back(2.1f);
  t.type.push_back(3.0f);
  const std::size_t n = t.type.size();
  std::vector<float> x(3 * n, 50.0f), v(3 * n, 0.0f), rho(n, 1000.0f);
  rho[200] = 600, rho[201] = 0;  // elastic and boundary: not checked
  StabilityMonitor monitor(t.box, t.type, LongRunStabilityOptions());
  rho[0] = rho[1] = 250;  // 2 of 200 liquid particles: 1%, tolerated
  monitor.Observe(0, x.data(), v.data(), rho.data());
  EXPECT_TRUE(monitor.report().pass());
  rho[2] = 1400;  // 3 of 200: 1.5%
  monitor.Observe(4e-4, x.data(), v.data(), rho.data());
  EXPECT_FALSE(monitor.report().pass());
  EXPECT_EQ(monitor.report().density_out_of_range.first_frame, 1u);
  EXPECT_DOUBLE_EQ(monitor.report().max_density_outside_fraction, 0.015);
  EXPECT_EQ(monitor.report().frames, 2u);
}

// The help texts of `run --stability`, `ci validate --stability` and `check stability` say the
// gate from its own thresholds: a changed threshold changes the words.
TEST(StabilityMonitor, TheGatesDescriptionComesFromItsThresholds) {
  EXPECT_EQ(DescribeStability(LongRunStabilityOptions()),
            "NaN, escapes (over 1 cu outside the box), kinetic blow-up (mean speed over 1 m/s), "
            "density 700-1300 kg/m^3 with at most 1% of the liquid particles outside");
  StabilityOptions o;
  o.box_tolerance_cu = 0.5, o.speed_limit_m_s = 2, o.density_min = 900;
  EXPECT_EQ(DescribeStability(o),
            "NaN, escapes (over 0.5 cu outside the box), kinetic blow-up (mean speed over 2 m/s), "
            "density 900-5000 kg/m^3 for every one of the particles");
}

TEST(StabilityMonitor, FedFrameByFrameAgreesWithCheckStability) {
  Trajectory t = TwoLiquidParticles(10);
  t.position(5, 1)[0] = 12.5f;
  t.velocities[(7 * 2 + 0) * 3] = 50.0f;
  const StabilityReport whole = CheckStability(t);
  StabilityMonitor monitor(t.box, t.type);
  for (std::size_t f = 0; f < t.frame_count(); ++f)
    monitor.Observe(t.time_s[f], t.position(f, 0), &t.velocities[f * 6], &t.density[f * 2]);
  EXPECT_EQ(monitor.report().ToJson(), whole.ToJson());
}

// A threshold of NaN made every comparison false, so a trajectory that escapes its box passed
// (`owval check stability --box-tolerance nan` exited 0): thresholds out of range are bad input.
TEST(Stability, ThresholdsThatWouldPassEverythingAreInputErrors) {
  Trajectory escaped = TwoLiquidParticles(3);
  escaped.position(2, 1)[0] = 50.0f;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const auto& set : std::vector<std::function<void(StabilityOptions*)>>{
           [&](StabilityOptions* o) { o->box_tolerance_cu = nan; },
           [&](StabilityOptions* o) { o->box_tolerance_cu = -1; },
           [&](StabilityOptions* o) { o->speed_limit_m_s = nan; },
           [&](StabilityOptions* o) { o->speed_limit_m_s = 0; },
           [&](StabilityOptions* o) { o->density_max = nan; },
           [&](StabilityOptions* o) { o->density_outside_fraction = 2; },
       }) {
    StabilityOptions o;
    set(&o);
    EXPECT_THROW(CheckStability(escaped, o), InputError);
  }
  EXPECT_FALSE(CheckStability(escaped).pass());
  const Trajectory t = TwoLiquidParticles(3);
  IncompressibilityOptions nan_limit;
  nan_limit.limit = nan;
  EXPECT_THROW(CheckIncompressibility(t, nan_limit), InputError);
  IncompressibilityOptions zero_density;
  zero_density.rest_density = 0;
  EXPECT_THROW(CheckIncompressibility(t, zero_density), InputError);
}

TEST(Incompressibility, MeasuresMeanAndMaxDeviation) {
  Trajectory t = TwoLiquidParticles(3);
  t.density = {1000, 1000, 1000, 1030, 1000, 1000};  // frame 1 particle 1 is 3% dense
  const IncompressibilityReport r = CheckIncompressibility(t);
  EXPECT_NEAR(r.max_deviation, 0.03, 1e-6);
  EXPECT_NEAR(r.mean_deviation, 0.0075, 1e-6);  // 0.03 over 4 particle-frames (frame 0 skipped)
  EXPECT_EQ(*r.worst_frame, 1u);
  EXPECT_FALSE(r.pass());
  t.density[3] = 1005;
  EXPECT_TRUE(CheckIncompressibility(t).pass());
}

TEST(Incompressibility, RefusesTrajectoryWithoutDensity) {
  EXPECT_THROW(CheckIncompressibility(testing::BundledOneSprigRun()), InputError);
  const Trajectory sprig = testing::BundledOneSprigRun();
  EXPECT_THROW(CheckIncompressibility(*MemoryFrameSource(sprig)), InputError);
}

TEST(Incompressibility, FrameByFrameGivesTheWholeTrajectorysReport) {
  Trajectory t = TwoLiquidParticles(3);
  t.density = {1000, 1000, 1000, 1030, 1000, 990};
  EXPECT_EQ(CheckIncompressibility(*MemoryFrameSource(t)).ToJson(),
            CheckIncompressibility(t).ToJson());
}

}  // namespace
}  // namespace owval::compare
