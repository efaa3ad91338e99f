// The checklist's verdict rules on small constructed directories, without running a pipeline
// (cli/tests/checklist_test.cpp covers every item end to end on a real one).
#include <gtest/gtest.h>
#include <png.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "owval/ci/checklist.hpp"
#include "owval/testing/scratch_directory.hpp"
#include "owval/testing/test_files.hpp"
#include "owval/trajectory/formats.hpp"
#include "owval/trajectory/track.hpp"

namespace owval::ci {
namespace {
namespace fs = std::filesystem;

const fs::path& kOneSprig = testing::kBundledOneSprig;

fs::path Fresh(const std::string& name) { return owval::testing::TestScratch(name); }

const ChecklistItem& Item(const ChecklistReport& r, int number) {
  for (const ChecklistItem& i : r.items)
    if (i.number == number) return i;
  throw std::runtime_error("no item " + std::to_string(number));
}

TEST(ChecklistUnit, AnEmptyDirectoryIsNotReadyAndSaysWhy) {
  const ChecklistReport r = RunChecklist(Fresh("empty"));
  EXPECT_EQ(r.verdict, Verdict::kUnreviewable);
  EXPECT_EQ(r.exit_code(), 1);
  EXPECT_FALSE(r.parity);
  ASSERT_FALSE(r.blocking.empty());
  EXPECT_EQ(r.items.size(), 10u);
  for (const ChecklistItem& i : r.items) EXPECT_FALSE(i.pass) << i.number;
}

// The caller's reference: one_sprig's bundled Sibernetic run.
ChecklistOptions WithReference() {
  ChecklistOptions options;
  options.caller_reference = kOneSprig;
  options.caller_reference_source = kOneSprig.string();
  return options;
}

TEST(ChecklistUnit, IdenticalTrajectoriesPassParityButMissingEvidenceBlocks) {
  const fs::path dir = Fresh("identical");
  fs::copy_file(kOneSprig, dir / "reference.txt");
  fs::copy_file(kOneSprig, dir / "candidate.txt");
  const ChecklistReport r = RunChecklist(dir, WithReference());
  ASSERT_TRUE(r.parity);
  EXPECT_TRUE(r.parity_pass());
  EXPECT_TRUE(Item(r, 2).pass);   // the reference trajectory
  EXPECT_TRUE(Item(r, 3).pass);   // the candidate trajectory
  EXPECT_FALSE(Item(r, 1).pass);  // no prediction.json: blocking
  EXPECT_EQ(r.verdict, Verdict::kNotReady);
}

// A candidate equal to the reference is a perfect port or a copy: the report says so (not a gate:
// owval's PCISPH is byte-identical to Sibernetic's runs by design), with the producer it records.
TEST(ChecklistUnit, ACandidateEqualToTheReferenceIsNamedAsAPerfectPortOrACopy) {
  const fs::path dir = Fresh("copy");
  fs::copy_file(kOneSprig, dir / "reference.txt");
  fs::copy_file(kOneSprig, dir / "candidate.txt");
  const ChecklistReport copy = RunChecklist(dir, WithReference());
  EXPECT_TRUE(copy.parity_pass());
  EXPECT_NE(copy.candidate_note.find("a perfect port"), std::string::npos) << copy.candidate_note;
  EXPECT_NE(copy.candidate_note.find("no producer (none recorded)"), std::string::npos);
  EXPECT_NE(copy.ToMarkdown().find("**candidate** — the candidate equals the reference"),
            std::string::npos);
  // One coordinate of one late frame off by 1e-3 cu: no longer equal, no note.
  Trajectory moved = ReadTrajectory(kOneSprig);
  moved.position(moved.frame_count() - 1, 0)[0] += 1e-3f;
  fs::remove(dir / "candidate.txt");
  WriteTrajectory(moved, dir / "candidate.h5");
  EXPECT_EQ(RunChecklist(dir, WithReference()).candidate_note, "");
}

// The first frames of one_sprig's run: up to `fraction` of its duration.
Trajectory FirstPart(double fraction) {
  const Trajectory full = ReadTrajectory(kOneSprig);
  Trajectory part;
  part.box = full.box, part.type = full.type;
  part.time_step_s = full.time_step_s, part.log_step = full.log_step;
  for (std::size_t f = 0; f < full.frame_count() * fraction; ++f)
    part.AppendFrame(full.time_s[f], full.position(f, 0));
  return part;
}

// A run stopped at 98.6% of the reference's duration (Ctrl-C, or a NaN in its last 1.4%) passed
// the window gate (1.4% < 2%) and item 3: the checklist said ready for a run that did not finish.
// Its own record says it is partial; a finished run of the same length still passes item 3.
TEST(ChecklistUnit, APartialCandidateFailsItemThree) {
  const fs::path dir = Fresh("partial");
  fs::copy_file(kOneSprig, dir / "reference.txt");
  Trajectory stopped = FirstPart(0.986);
  WriteTrajectory(stopped, dir / "candidate.h5");
  const ChecklistReport finished = RunChecklist(dir, WithReference());
  EXPECT_TRUE(Item(finished, 3).pass) << Item(finished, 3).detail;
  EXPECT_TRUE(finished.parity_pass()) << finished.parity->FailedGates();
  stopped.provenance["partial"] = "1";
  fs::remove(dir / "candidate.h5");
  WriteTrajectory(stopped, dir / "candidate.h5");
  const ChecklistReport r = RunChecklist(dir, WithReference());
  EXPECT_FALSE(Item(r, 3).pass);
  EXPECT_NE(Item(r, 3).detail.find("partial: its own record says"), std::string::npos)
      << Item(r, 3).detail;
  EXPECT_EQ(r.verdict, Verdict::kUnreviewable);
}

// The same directory without a reference of the caller's: nothing says reference.txt is not the
// candidate under another name.
TEST(ChecklistUnit, WithoutTheCallersReferenceItemTwoFails) {
  const fs::path dir = Fresh("no_callers_reference");
  fs::copy_file(kOneSprig, dir / "reference.txt");
  fs::copy_file(kOneSprig, dir / "candidate.txt");
  const ChecklistReport r = RunChecklist(dir);
  EXPECT_FALSE(Item(r, 2).pass);
  EXPECT_NE(Item(r, 2).detail.find("--reference FILE"), std::string::npos) << Item(r, 2).detail;
  EXPECT_EQ(r.verdict, Verdict::kUnreviewable);
}

TEST(ChecklistUnit, AMalformedPredictionFailsItemOneNamingTheField) {
  const fs::path dir = Fresh("malformed");
  fs::copy_file(kOneSprig, dir / "reference.txt");
  fs::copy_file(kOneSprig, dir / "candidate.txt");
  std::ofstream(dir / "prediction.json")
      << R"({"track": {"particle": 0, "axis": "y"}, "predictions": [{"quantity": "equilibrium"}]})";
  const ChecklistReport r = RunChecklist(dir);
  EXPECT_FALSE(Item(r, 1).pass);
  EXPECT_NE(Item(r, 1).detail.find("\"predictions[0].value\": expected a finite number"),
            std::string::npos)
      << Item(r, 1).detail;
  EXPECT_FALSE(Item(r, 10).pass);
}

// one_sprig's particle 0 raised by 0.2 cu (5.9% of its 3.39 cu range, so the frames gate fails at
// DD001's 5%), the offset growing evenly over frames 1-100 (a step at frame 1 would be a jump
// that acceleration.worst_stencil fails by itself). A caller's manifest with frame_threshold 0.1
// let it pass, and the checklist said nothing of the loosened gate: the parity gate passed.
TEST(ChecklistUnit, ACandidatePassingOnlyLoosenedGatesFailsTheParityGateNamingThem) {
  const fs::path dir = Fresh("loosened");
  fs::copy_file(kOneSprig, dir / "reference.txt");
  Trajectory raised = ReadTrajectory(kOneSprig);
  for (std::size_t f = 1; f < raised.frame_count(); ++f)
    raised.position(f, 0)[1] += float(0.2 * std::min(1.0, double(f) / 100));
  WriteTrajectory(raised, dir / "candidate.h5");
  ChecklistOptions loose = WithReference();
  loose.gates.frame = {0.1, compare::ThresholdSource::kManifest};
  const ChecklistReport r = RunChecklist(dir, loose);
  ASSERT_TRUE(r.parity);
  EXPECT_TRUE(r.parity->pass());  // at the caller's thresholds
  ASSERT_EQ(r.loosened_thresholds.size(), 1u);
  EXPECT_EQ(r.loosened_thresholds[0], "frame_threshold 0.1 (manifest; default 0.05)");
  EXPECT_EQ(r.failed_at_default_thresholds, "frames, frames.position");
  EXPECT_FALSE(r.parity_pass());
  EXPECT_NE(r.ToMarkdown().find("**gates loosened by the caller** — frame_threshold 0.1 "
                                "(manifest; default 0.05): at the defaults it FAILS: frames, "
                                "frames.position"),
            std::string::npos)
      << r.ToMarkdown();
  const std::string blocking = r.blocking.empty() ? "" : r.blocking.back();
  EXPECT_NE(blocking.find("parity gate (passes only with thresholds looser than DD001's"),
            std::string::npos)
      << blocking;
  // The same loosened gate over a candidate that passes the defaults: the gate is named, the
  // parity gate passes.
  fs::remove(dir / "candidate.h5");
  fs::copy_file(kOneSprig, dir / "candidate.txt");
  const ChecklistReport honest = RunChecklist(dir, loose);
  EXPECT_TRUE(honest.parity_pass());
  EXPECT_EQ(honest.loosened_thresholds.size(), 1u);
  EXPECT_NE(honest.ToMarkdown().find("the candidate passes the defaults too"), std::string::npos);
  // Tightened gates are not loosened ones.
  ChecklistOptions tight = WithReference();
  tight.gates.frame = {0.01, compare::ThresholdSource::kManifest};
  EXPECT_TRUE(RunChecklist(dir, tight).loosened_thresholds.empty());
}

// Mutation audit (2026-11-30, docs/checklist.md): cases no earlier test decided.

// A wall particle does not move: its frame gate agrees with any candidate that leaves it alone,
// so the parity gate fails and blocks, naming why. (cli/tests/checklist_test.cpp's case is a
// failing candidate, which other gates fail anyway: the parity gate passed a still track.)
TEST(ChecklistUnit, AStillTrackedQuantityFailsTheParityGate) {
  const fs::path dir = Fresh("still_track");
  fs::copy_file(kOneSprig, dir / "reference.txt");
  fs::copy_file(kOneSprig, dir / "candidate.txt");
  ChecklistOptions still = WithReference();
  still.track = Track{};
  still.track->particle = 1;  // a wall particle, y
  const ChecklistReport r = RunChecklist(dir, still);
  ASSERT_TRUE(r.parity);
  EXPECT_TRUE(r.parity->pass());  // every gate, the frame gate included, agrees
  EXPECT_FALSE(r.tracked_moves);
  EXPECT_FALSE(r.parity_pass());
  const std::string blocking = r.blocking.empty() ? "" : r.blocking.back();
  EXPECT_NE(blocking.find("parity gate (particle 1 y does not move in the reference"),
            std::string::npos)
      << blocking;
  EXPECT_TRUE(RunChecklist(dir, WithReference()).parity_pass());  // particle 0 y moves
}

// One frame is no run: items 2 and 3 need two, and the directory is unreviewable (it was "not
// ready", for the parity gate, when one frame sufficed), the caller's reference one frame too.
TEST(ChecklistUnit, OneFrameRunsAreUnreviewable) {
  const fs::path dir = Fresh("one_frame");
  const Trajectory one = FirstPart(1e-9);
  ASSERT_EQ(one.frame_count(), 1u);
  WriteTrajectory(one, dir / "reference.h5");
  WriteTrajectory(one, dir / "candidate.h5");
  ChecklistOptions options;
  options.caller_reference = dir / "reference.h5";
  const ChecklistReport r = RunChecklist(dir, options);
  for (int i : {2, 3}) {
    EXPECT_FALSE(Item(r, i).pass) << i;
    EXPECT_NE(Item(r, i).detail.find(": 1 frames, "), std::string::npos) << Item(r, i).detail;
    EXPECT_NE(Item(r, i).detail.find("(expected at least 2 frames)"), std::string::npos)
        << Item(r, i).detail;
  }
  EXPECT_EQ(r.verdict, Verdict::kUnreviewable);
}

// A PNG of 2x2 black pixels, as libpng writes it.
void WritePng(const fs::path& file) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = 2, image.height = 2, image.format = PNG_FORMAT_GRAY;
  const unsigned char black[4] = {0, 0, 0, 0};
  ASSERT_TRUE(png_image_write_to_file(&image, file.c_str(), 0, black, 0, nullptr)) << file;
}

// frames/ of `dir`: the PNGs `images` and frames.json's entries, one per frame of `at` (the same
// index in both runs), each naming its image of `named` and labelled with particle 0 y there, in
// `reference` and in `candidate`.
void WriteFrames(const fs::path& dir, const std::vector<std::string>& images,
                 const std::vector<std::size_t>& at, const std::vector<std::string>& named,
                 const Trajectory& reference, const Trajectory& candidate) {
  fs::create_directories(dir / "frames");
  for (const std::string& image : images) WritePng(dir / "frames" / image);
  nlohmann::json entries = nlohmann::json::array();
  for (std::size_t i = 0; i < at.size(); ++i)
    entries.push_back({{"image", named[i]},
                       {"reference_frame", at[i]},
                       {"candidate_frame", at[i]},
                       {"reference_value", Track{}.ValueAt(reference, at[i])},
                       {"candidate_value", Track{}.ValueAt(candidate, at[i])}});
  std::ofstream(dir / "frames/frames.json")
      << nlohmann::json{{"track", Track{}.ToJson()}, {"frames", entries}}.dump(2);
}

// Item 5 asks for at least 3 PNGs and at least 3 entries: 3 and 3 pass; 2 entries (3 PNGs), or 2
// PNGs (3 entries, two naming one image) fail. Either count one short passed before. And the frame
// gate holds at the sampled frames: one_sprig's particle 0 raised 0.2 cu (5.9% of its range) fails
// there, which the item did not say when the parity gate's own frame gate failed it too.
TEST(ChecklistUnit, ItemFiveNeedsThreeImagesAndThreeEntriesWithinTheFrameGate) {
  const Trajectory run = FirstPart(0.1);  // 250 frames, 7 periods: four checklists in seconds
  ChecklistOptions options;
  options.caller_reference = Fresh("caller") / "reference.h5";
  WriteTrajectory(run, options.caller_reference);
  const auto item_five = [&](const std::string& name, const std::vector<std::string>& images,
                             const std::vector<std::size_t>& at,
                             const std::vector<std::string>& named, const Trajectory& candidate) {
    const fs::path dir = Fresh(name);
    WriteTrajectory(run, dir / "reference.h5");
    WriteTrajectory(candidate, dir / "candidate.h5");
    WriteFrames(dir, images, at, named, run, candidate);
    return Item(RunChecklist(dir, options), 5);
  };
  const std::vector<std::string> abc = {"a.png", "b.png", "c.png"};
  const ChecklistItem three = item_five("three", abc, {0, 15, 100}, abc, run);
  EXPECT_TRUE(three.pass) << three.detail;
  const ChecklistItem two_entries = item_five("two_entries", abc, {0, 15}, {"a.png", "b.png"}, run);
  EXPECT_FALSE(two_entries.pass) << two_entries.detail;
  EXPECT_NE(two_entries.detail.find("3 PNGs decode; 2/2 labelled values agree"), std::string::npos)
      << two_entries.detail;
  const ChecklistItem two_images =
      item_five("two_images", {"a.png", "b.png"}, {0, 15, 100}, {"a.png", "b.png", "b.png"}, run);
  EXPECT_FALSE(two_images.pass) << two_images.detail;
  EXPECT_NE(two_images.detail.find("2 PNGs decode; 3/3 labelled values agree"), std::string::npos)
      << two_images.detail;
  Trajectory raised = run;
  for (std::size_t f = 1; f < raised.frame_count(); ++f) raised.position(f, 0)[1] += 0.2f;
  const ChecklistItem off_gate = item_five("off_gate", abc, {0, 15, 100}, abc, raised);
  EXPECT_FALSE(off_gate.pass) << off_gate.detail;
  EXPECT_NE(off_gate.detail.find("3/3 labelled values agree"), std::string::npos)
      << off_gate.detail;
  EXPECT_NE(off_gate.detail.find(", FAILS at frames"), std::string::npos) << off_gate.detail;
}

// fd_tests.json with no test proves nothing: item 7 fails (it passed when "every test passes"
// was the whole rule), and one passing test passes it.
TEST(ChecklistUnit, AnEmptyListOfFiniteDifferenceTestsFailsItemSeven) {
  const fs::path dir = Fresh("no_fd_tests");
  std::ofstream(dir / "fd_tests.json") << R"({"tests": []})";
  const ChecklistItem none = Item(RunChecklist(dir), 7);
  EXPECT_FALSE(none.pass);
  EXPECT_EQ(none.detail, "0/0 finite-difference tests pass");
  std::ofstream(dir / "fd_tests.json")
      << R"({"tests": [{"name": "stretch", "pass": true, "relative_error": 1e-4,
                        "tolerance": 1e-3}]})";
  EXPECT_TRUE(Item(RunChecklist(dir), 7).pass);
}

// "pass": true alone is a claim without its evidence: the test counts as failing, by name.
TEST(ChecklistUnit, AFiniteDifferenceTestWithoutItsErrorAndToleranceFailsItemSeven) {
  const fs::path dir = Fresh("fd_test_claim_only");
  std::ofstream(dir / "fd_tests.json") << R"({"tests": [{"name": "stretch", "pass": true}]})";
  const ChecklistItem item = Item(RunChecklist(dir), 7);
  EXPECT_FALSE(item.pass);
  EXPECT_EQ(item.detail,
            "0/1 finite-difference tests pass (stretch says pass, but gives no relative_error "
            "and tolerance)");
}

}  // namespace
}  // namespace owval::ci
