// The stale_frames gate: a candidate frame that repeats the one before while the reference moves
// (a frame written twice). One such frame in demo1 or one_sprig passed every other gate
// (docs/checklist.md, "Attacks measured (round 7)").
#include <gtest/gtest.h>

#include "edited_runs.hpp"
#include "owval/compare/parity.hpp"
#include "owval/testing/reference_runs.hpp"

namespace owval::compare {
namespace {

// `t` with frame `f` a copy of frame f - 1 (its time kept).
Trajectory WrittenTwice(const Trajectory& t, std::size_t f) {
  Trajectory out = t;
  for (std::size_t p = 0; p < out.particle_count(); ++p)
    for (int a = 0; a < 3; ++a) out.position(f, p)[a] = out.position(f - 1, p)[a];
  return out;
}

TEST(StaleFrames, OneSprigWithAFrameWrittenTwiceFailsOnlyThis) {
  const Trajectory& run = testing::BundledOneSprigRun();
  const ParityReport same = CompareTrajectories(run, run, {});
  EXPECT_EQ(same.gate("stale_frames")->value, 0.0);
  EXPECT_EQ(same.gate("stale_frames")->status, GateStatus::kPass);
  const ParityReport stale = CompareTrajectories(run, WrittenTwice(run, 1250), {});
  EXPECT_EQ(stale.FailedGates(), "stale_frames");  // frames: 0.07% of the range
  EXPECT_EQ(stale.gate("stale_frames")->value, 1.0);
  EXPECT_NE(stale.gate("stale_frames")->detail.find("at reference frame 1250"), std::string::npos)
      << stale.gate("stale_frames")->detail;
}

TEST(StaleFrames, ASceneAtRestIsNoStaleFrame) {
  const Trajectory still = testing_edits::ParticleAtRest(4);
  Trajectory rounded = still;  // the reference moved by less than a print's rounding
  rounded.position(2, 0)[0] += 2e-5f;
  // A copy: the report is a temporary.
  const Gate g = *CompareTrajectories(rounded, still, {}).gate("stale_frames");
  EXPECT_EQ(g.value, 0.0) << g.detail;
}

TEST(StaleFramesParity, Demo1WithAFrameWrittenTwiceFailsOnlyThis) {
  OWVAL_REQUIRE_DEMO1();
  const Trajectory& demo1 = *testing::SiberneticDemo1Run();
  const ParityReport r = CompareTrajectories(demo1, WrittenTwice(demo1, 250), {});
  EXPECT_EQ(r.FailedGates(), "stale_frames");
  EXPECT_EQ(r.gate("stale_frames")->value, 1.0);
  EXPECT_TRUE(CompareTrajectories(demo1, demo1, {}).pass());
}

// `t` logged twice as often, the frame between each two of its frames a copy of the one before
// (at the time halfway).
Trajectory LoggedTwiceAsOftenWithCopies(const Trajectory& t) {
  Trajectory out = t;
  out.time_s.clear();
  out.positions.clear();
  out.log_step = t.log_step;
  out.time_step_s = t.time_step_s / 2;
  for (std::size_t f = 0; f < t.frame_count(); ++f) {
    out.AppendFrame(t.time_s[f], t.position(f, 0));
    if (f + 1 < t.frame_count())
      out.AppendFrame(0.5 * (t.time_s[f] + t.time_s[f + 1]), t.position(f, 0));
  }
  return out;
}

// Logged twice as often with every other frame a copy: the copies are no paired frame, and no
// gate read them (round 5's "every odd frame a copy", caught at the reference's own log step,
// passed so). An honest candidate logged twice as often measures 0.
TEST(StaleFrames, CopiesBetweenThePairedFramesFail) {
  const Trajectory& run = testing::BundledOneSprigRun();
  const ParityReport copies = CompareTrajectories(run, LoggedTwiceAsOftenWithCopies(run), {});
  const Gate& g = *copies.gate("stale_frames");
  EXPECT_EQ(g.status, GateStatus::kFail) << g.detail;
  // Every copy but the first: the spring starts at rest, and over the first interval the
  // reference moves by less than two prints' rounding.
  EXPECT_EQ(g.value, double(run.frame_count() - 2)) << g.detail;
  const Trajectory coarse = testing_edits::EveryNthFrame(run, 2);
  const ParityReport honest = CompareTrajectories(coarse, run, {});
  EXPECT_EQ(honest.gate("stale_frames")->value, 0.0) << honest.gate("stale_frames")->detail;
  EXPECT_EQ(CompareTrajectories(coarse, LoggedTwiceAsOftenWithCopies(coarse), {})
                .gate("stale_frames")
                ->value,
            double(coarse.frame_count() - 2));
}

// `t` with frames first, first + every, ... read back mid-update: every moving particle but
// `fresh` of them at the frame before's position (a GPU read-back racing the step).
Trajectory ReadBackMidUpdate(const Trajectory& t, std::size_t first, std::size_t every,
                             std::size_t fresh) {
  Trajectory out = t;
  for (std::size_t f = first; f < out.frame_count(); f += every) {
    std::size_t kept = 0;
    for (std::size_t p = 0; p < out.particle_count(); ++p) {
      if (KindOf(out.type[p]) == ParticleKind::kBoundary || kept++ < fresh) continue;
      for (int a = 0; a < 3; ++a) out.position(f, p)[a] = t.position(f - 1, p)[a];
    }
  }
  return out;
}

// demo1's frames 250, 260, ... with only particle 0 (the tracked one) new passed every gate: no
// frame repeated the one before whole. Half the moving particles held still is a stale frame.
TEST(StaleFramesParity, Demo1ReadBackMidUpdateFails) {
  OWVAL_REQUIRE_DEMO1();
  const Trajectory& demo1 = *testing::SiberneticDemo1Run();
  const std::size_t moving =
      demo1.count(ParticleKind::kElastic) + demo1.count(ParticleKind::kLiquid);
  for (const std::size_t fresh : {std::size_t{1}, moving / 3}) {
    const ParityReport r = CompareTrajectories(demo1, ReadBackMidUpdate(demo1, 250, 10, fresh), {});
    const Gate& g = *r.gate("stale_frames");
    EXPECT_EQ(g.status, GateStatus::kFail) << fresh << ": " << g.detail;
    EXPECT_EQ(g.value, 25.0) << fresh;
    EXPECT_NE(g.detail.find("at reference frame 250, "), std::string::npos) << g.detail;
  }
  // Under half held still: passed by this gate (honest runs hold up to 2.6% still where the
  // reference moves: demo1_1s's cube at rest).
  const ParityReport fewer =
      CompareTrajectories(demo1, ReadBackMidUpdate(demo1, 250, 10, moving / 2 + 2), {});
  EXPECT_EQ(fewer.gate("stale_frames")->value, 0.0);
}

}  // namespace
}  // namespace owval::compare
