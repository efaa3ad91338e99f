// Every checklist item's failing case (issue 20): a ready pipeline directory, made once, is
// copied and one artifact is broken per test; the checklist must name that item.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>

#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "owval/testing/git_history.hpp"

namespace owval::testing {
namespace {
namespace fs = std::filesystem;

class Checklist : public ::testing::Test {
 protected:
  // The shared ready directory (cli_support.hpp); made, it holds "complete".
  static fs::path Ready() {
    const fs::path d = ReadyPipelineDirectory();
    EXPECT_TRUE(fs::exists(d / "complete")) << "owval pipeline one_sprig failed in " << d;
    return d;
  }

  // A copy of the ready directory to break.
  fs::path Copy(const std::string& name) {
    const fs::path d = Scratch() / ("checklist_" + name);
    fs::remove_all(d);
    fs::copy(Ready(), d, fs::copy_options::recursive);
    fs::remove(d / "complete");
    return d;
  }

  // The checklist's report on dir, judged against the ready run's reference (one_sprig's
  // bundled Sibernetic run) unless FLAGS name the scenario.
  static nlohmann::json Judge(const fs::path& dir, int expected_exit,
                              const std::string& flags = "") {
    const bool scenario = flags.find("--scenario") != std::string::npos;
    return JudgeAlone(
        dir, expected_exit,
        flags + (scenario ? "" : " --reference " + (Ready() / "reference.h5").string()));
  }
  // The same with only FLAGS: no reference of the caller's unless they give one.
  static nlohmann::json JudgeAlone(const fs::path& dir, int expected_exit,
                                   const std::string& flags = "") {
    const Result r = Owval("checklist " + dir.string() + " --json " + flags);
    EXPECT_EQ(r.exit_code, expected_exit) << r.out << r.err;
    return nlohmann::json::parse(r.out);
  }

  static void Write(const fs::path& file, const std::string& text) { std::ofstream(file) << text; }

  // `sides` of d (reference.h5, candidate.h5) replaced by one_sprig run with ARGS.
  static void ReplaceWithRun(const fs::path& d, const std::string& args,
                             std::initializer_list<const char*> sides) {
    const fs::path run = d.string() + "_run";
    ASSERT_EQ(Owval("run one_sprig --no-fields " + args + " --out " + run.string()).exit_code, 0);
    for (const char* side : sides)
      fs::copy_file(run / "trajectory.h5", d / side, fs::copy_options::overwrite_existing);
  }
  static constexpr const char* kFailingCandidate = "--set elasticity_coefficient=3.3e8";

  // frames/ of d made again from its trajectories at 0, 15, 100 and 200, with FLAGS.
  static void Reframe(const fs::path& d, const std::string& flags = "") {
    fs::remove_all(d / "frames");
    ASSERT_EQ(
        Owval("frames " + (d / "reference.h5").string() + " " + (d / "candidate.h5").string() +
              " --at 0,15,100,200 " + flags + " -o " + (d / "frames").string())
            .exit_code,
        0);
  }

  static void EditJson(const fs::path& file, const std::function<void(nlohmann::json&)>& edit) {
    nlohmann::json j = nlohmann::json::parse(Slurp(file));
    edit(j);
    Write(file, j.dump(2));
  }

  // The ready fit stopped at iteration 1 (loss 1.9e-3, above 1e-4), its first target (period)
  // edited by `edit`, which returns the factor that edit multiplies the target's residuals by; the
  // residuals, every loss and the final loss made to match, as a forger would write them.
  static void ForgeFirstTargetAtIterationOne(const fs::path& d,
                                             const std::function<double(nlohmann::json&)>& edit) {
    EditJson(d / "fit/history.json", [&](nlohmann::json& h) {
      h["iterations"].erase(2);
      const double factor = edit(h["targets"][0]);
      for (auto& it : h["iterations"]) {
        it["residuals"][0] = it["residuals"][0].get<double>() * factor;
        double loss = 0;
        for (const auto& r : it["residuals"]) loss += r.get<double>() * r.get<double>();
        it["loss"] = loss;
      }
      h["final"] = {{"loss", h["iterations"][1]["loss"]},
                    {"parameters", h["iterations"][1]["parameters"]}};
    });
  }
};

bool ItemPasses(const nlohmann::json& report, int item) {
  return report["items"][std::size_t(item - 1)]["pass"].get<bool>();
}

TEST_F(Checklist, ReadyDirectoryPassesEveryItemAndTheParityGate) {
  const auto j = Judge(Ready(), 0);
  EXPECT_EQ(j["verdict"], "ready");
  for (int i = 1; i <= 10; ++i) EXPECT_TRUE(ItemPasses(j, i)) << i;
  EXPECT_TRUE(j["parity"]["pass"].get<bool>());
  // Item 1's order cannot be seen in a plain directory, and the report says so.
  EXPECT_NE(j["items"][0]["detail"].get<std::string>().find("NOT CHECKED"), std::string::npos);
  EXPECT_NE(j["items"][1]["detail"].get<std::string>().find("the caller's reference"),
            std::string::npos)
      << j["items"][1].dump();
  // Item 6 reran the fit's best parameters and got the history's residuals back.
  EXPECT_NE(j["items"][5]["detail"].get<std::string>().find("rerun at the best parameters"),
            std::string::npos)
      << j["items"][5].dump();
}

// `owval pipeline one_sprig` through the executable: the shared ready directory is that run
// (cli_support.hpp), judged here against the scenario's own reference; without its video, a copy
// is not ready.
using CliPipeline = Checklist;

TEST_F(CliPipeline, OneSprigProducesAReadyDirectoryAndMissingVideoMakesItNotReady) {
  const fs::path dir = Copy("pipeline");
  for (const char* f :
       {"prediction.json", "reference.h5", "candidate.h5", "sxs.mp4", "frames/frames.json",
        "fit/history.json", "fd_tests.json", "parameters.json", "changes.md", "reconcile.json",
        "index.html", "index.md", "parity.json", "scenario"})
    EXPECT_TRUE(fs::exists(dir / f)) << f;
  const Result ready = Owval("checklist " + dir.string() + " --json --scenario one_sprig");
  EXPECT_EQ(ready.exit_code, 0);
  const auto verdict = nlohmann::json::parse(ready.out);
  EXPECT_EQ(verdict["verdict"], "ready");
  for (const auto& item : verdict["items"]) EXPECT_TRUE(item["pass"].get<bool>()) << item.dump();
  fs::remove(dir / "sxs.mp4");
  const Result missing = Owval("checklist " + dir.string() + " --scenario one_sprig");
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.out.find("not ready"), std::string::npos) << missing.out;
}

// `--markdown DIR/candidate.h5` would have replaced the evidence with the report on it.
TEST_F(Checklist, AMarkdownOutputOverTheEvidenceIsRefused) {
  const fs::path d = Copy("markdown_over_evidence");
  const std::string before = Slurp(d / "candidate.h5");
  const Result r = Owval("checklist " + d.string() + " --scenario one_sprig --markdown " +
                         (d / "candidate.h5").string());
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("is also an input of this command"), std::string::npos) << r.err;
  EXPECT_EQ(Slurp(d / "candidate.h5"), before);
  EXPECT_EQ(Owval("checklist " + d.string() + " --scenario one_sprig --markdown " +
                  (d / "comment.md").string())
                .exit_code,
            0);
}

// Without --scenario or --reference nothing says the directory's reference is the reference:
// item 2 fails and names the two flags.
TEST_F(Checklist, WithoutTheCallersReferenceItIsUnreviewable) {
  const auto j = JudgeAlone(Ready(), 1);
  EXPECT_EQ(j["verdict"], "unreviewable");
  EXPECT_FALSE(ItemPasses(j, 2));
  EXPECT_NE(j["items"][1]["detail"].get<std::string>().find("--scenario NAME or --reference FILE"),
            std::string::npos)
      << j["items"][1].dump();
}

// A failing candidate (k = 3.3e8) copied over the reference as text, which carries no record of
// what made it, with frames, video and prediction made from the pair: everything agrees with
// everything, and only the caller's reference tells.
TEST_F(Checklist, ACandidateCopiedOverTheReferenceIsUnreviewable) {
  const fs::path d = Copy("copied_reference");
  ASSERT_NO_FATAL_FAILURE(ReplaceWithRun(d, kFailingCandidate, {"candidate.h5"}));
  fs::remove(d / "reference.h5");
  ASSERT_EQ(Owval("convert " + (d / "candidate.h5").string() + " " + (d / "reference.txt").string())
                .exit_code,
            0);
  fs::remove_all(d / "frames");
  ASSERT_EQ(Owval("frames " + (d / "reference.txt").string() + " " + (d / "candidate.h5").string() +
                  " --at 0,15,100,200 -o " + (d / "frames").string())
                .exit_code,
            0);
  EXPECT_EQ(JudgeAlone(d, 1)["verdict"], "unreviewable");
  const auto j = Judge(d, 1);
  EXPECT_EQ(j["verdict"], "unreviewable");
  EXPECT_NE(j["items"][1]["detail"].get<std::string>().find("NOT the caller's reference"),
            std::string::npos)
      << j["items"][1].dump();
}

TEST_F(Checklist, Item1FailsOnAnEmptyPrediction) {
  const fs::path d = Copy("item1");
  EditJson(d / "prediction.json",
           [](nlohmann::json& j) { j["predictions"] = nlohmann::json::array(); });
  const auto j = Judge(d, 1);
  EXPECT_EQ(j["verdict"], "not ready");
  EXPECT_FALSE(ItemPasses(j, 1));
}

TEST_F(Checklist, Item1ChecksThePredictionWasCommittedBeforeTheTrajectories) {
  const fs::path late = Copy("item1_late");
  owval::testing::CommitInOrder(late,
                                {{"reference.h5", "candidate.h5"}, {"prediction.json"}, {"."}});
  auto j = Judge(late, 1, "--git-range base..HEAD");
  EXPECT_FALSE(ItemPasses(j, 1));
  EXPECT_NE(j["items"][0]["detail"].get<std::string>().find("AFTER"), std::string::npos);
  const fs::path early = Copy("item1_early");
  owval::testing::CommitInOrder(early,
                                {{"prediction.json"}, {"reference.h5", "candidate.h5"}, {"."}});
  j = Judge(early, 0, "--git-range base..HEAD");
  EXPECT_TRUE(ItemPasses(j, 1)) << j["items"][0].dump();
  // A malformed or unreadable range is bad input, named as given.
  EXPECT_EQ(Owval("checklist " + early.string() + " --git-range nonsense").exit_code, 2);
  const Result unreadable = Owval("checklist " + early.string() + " --git-range nosuch..HEAD");
  EXPECT_EQ(unreadable.exit_code, 2);
  EXPECT_NE(unreadable.err.find("--git-range nosuch..HEAD"), std::string::npos) << unreadable.err;
}

// The runs committed before the range, the prediction inside it: no trajectory was added in the
// range, but the prediction still came after them.
TEST_F(Checklist, Item1FailsWhenThePredictionFollowsRunsThatPredateTheRange) {
  const fs::path d = Copy("item1_runs_before_range");
  owval::testing::CommitInOrder(d, {{"reference.h5", "candidate.h5"}, {"prediction.json"}, {"."}});
  const auto j = Judge(d, 1, "--git-range HEAD~2..HEAD");
  EXPECT_FALSE(ItemPasses(j, 1));
  EXPECT_NE(j["items"][0]["detail"].get<std::string>().find("AFTER"), std::string::npos)
      << j["items"][0].dump();
}

TEST_F(Checklist, Items2And3MissingOrCorruptAreUnreviewable) {
  const fs::path d = Copy("item2");
  fs::remove(d / "reference.h5");
  auto j = Judge(d, 1);
  EXPECT_EQ(j["verdict"], "unreviewable");
  EXPECT_FALSE(ItemPasses(j, 2));
  const fs::path c = Copy("item3");
  Write(c / "candidate.h5", "not an HDF5 file");
  j = Judge(c, 1);
  EXPECT_EQ(j["verdict"], "unreviewable");
  EXPECT_FALSE(ItemPasses(j, 3));
}

TEST_F(Checklist, Item4FailsOnASinglePanelVideo) {
  const fs::path d = Copy("item4");
  ASSERT_EQ(Owval("render " + (d / "reference.h5").string() + " --max-frames 5 --size 320x320 -o " +
                  (d / "sxs.mp4").string())
                .exit_code,
            0);
  const auto j = Judge(d, 1);
  EXPECT_FALSE(ItemPasses(j, 4));
  EXPECT_NE(j["items"][3]["detail"].get<std::string>().find("not two panels"), std::string::npos);
}

// 5,000 bytes zeroed in the first (key) frame's data, which starts near the top of the file:
// libavcodec would conceal the damage and still hand out every frame; the checklist asks it not
// to. (H.264 has no checksums: damage the decoder cannot see, it cannot report.)
TEST_F(Checklist, Item4FailsOnADamagedVideo) {
  const fs::path d = Copy("item4_damaged");
  {
    std::fstream video(d / "sxs.mp4", std::ios::in | std::ios::out | std::ios::binary);
    video.seekp(2048);
    const std::string zeros(5000, '\0');
    video.write(zeros.data(), std::streamsize(zeros.size()));
  }
  const Result r = Owval("checklist " + d.string() + " --json --scenario one_sprig");
  EXPECT_EQ(r.exit_code, 1);
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_FALSE(ItemPasses(j, 4));
  EXPECT_NE(j["items"][3]["detail"].get<std::string>().find("damaged"), std::string::npos)
      << j["items"][3].dump();
  EXPECT_EQ(r.err, "");  // libavcodec's own complaints stay out of owval's output
}

// A video made before the candidate changed: the ready directory's sxs.mp4 shows the pipeline's
// candidate, and candidate.h5 is now another run (round 7's "rendered reference against
// reference" was ready: codec, shape and frame count say nothing of what a video shows). Its
// frames, drawn again from the directory's runs with the options recorded in it, differ.
TEST_F(Checklist, Item4FailsOnAVideoOfOtherRuns) {
  const fs::path d = Copy("item4_other_runs");
  ASSERT_NO_FATAL_FAILURE(ReplaceWithRun(d, kFailingCandidate, {"candidate.h5"}));
  const auto j = Judge(d, 1, "--scenario one_sprig");
  EXPECT_FALSE(ItemPasses(j, 4));
  const std::string detail = j["items"][3]["detail"].get<std::string>();
  EXPECT_NE(detail.find("does not show these two runs"), std::string::npos) << detail;
  // The ready directory's own video shows its runs.
  const auto ready = Judge(Copy("item4_ready"), 0, "--scenario one_sprig");
  EXPECT_TRUE(ItemPasses(ready, 4)) << ready["items"][3].dump();
  EXPECT_NE(ready["items"][3]["detail"].get<std::string>().find("drawn again from the two runs"),
            std::string::npos);
}

TEST_F(Checklist, Item5FailsWhenAListedImageIsMissing) {
  const fs::path d = Copy("item5_missing_image");
  const nlohmann::json frames = nlohmann::json::parse(Slurp(d / "frames/frames.json"));
  fs::remove(d / "frames" / frames["frames"][1]["image"].get<std::string>());
  const auto j = Judge(d, 1);
  EXPECT_FALSE(ItemPasses(j, 5));
  EXPECT_NE(j["items"][4]["detail"].get<std::string>().find("listed images missing"),
            std::string::npos)
      << j["items"][4].dump();
}

TEST_F(Checklist, Item5FailsWhenALabelledValueDisagreesWithTheTrajectory) {
  const fs::path d = Copy("item5");
  EditJson(d / "frames/frames.json",
           [](nlohmann::json& j) { j["frames"][1]["candidate_value"] = 99.0; });
  const auto j = Judge(d, 1);
  EXPECT_FALSE(ItemPasses(j, 5));
  EXPECT_TRUE(j["parity"]["pass"].get<bool>());  // the trajectories themselves agree
}

TEST_F(Checklist, Item5RefusesATrackThatDoesNotExist) {
  const fs::path d = Copy("item5_track");
  EditJson(d / "frames/frames.json", [](nlohmann::json& j) { j["track"]["particle"] = 100000000; });
  const auto j = Judge(d, 1);
  EXPECT_FALSE(ItemPasses(j, 5));
  EXPECT_NE(j["items"][4]["detail"].get<std::string>().find("100000000"), std::string::npos);
}

TEST_F(Checklist, Item6FailsOnAnUnconvergedFit) {
  const fs::path d = Copy("item6");
  EditJson(d / "fit/history.json", [](nlohmann::json& j) { j["converged"] = false; });
  const auto j = Judge(d, 1);
  EXPECT_EQ(j["verdict"], "not ready");
  EXPECT_FALSE(ItemPasses(j, 6));
}

// Item 6's detail in the report `j`, and that it failed.
std::string FailedItem6(const nlohmann::json& j) {
  EXPECT_EQ(j["verdict"], "not ready");
  EXPECT_FALSE(ItemPasses(j, 6));
  return j["items"][5]["detail"].get<std::string>();
}

// A forged history whose numbers agree with each other: every residual invented (1e-4 and
// below), each loss their sum of squares, the last the best, converged. Only the rerun of the
// best parameters can tell.
TEST_F(Checklist, Item6FailsOnAForgedSelfConsistentHistory) {
  const fs::path d = Copy("item6_forged");
  EditJson(d / "fit/history.json", [](nlohmann::json& h) {
    double scale = 1e-3;
    for (auto& it : h["iterations"]) {
      scale /= 10;
      double loss = 0;
      for (auto& r : it["residuals"]) r = scale, loss += scale * scale;
      it["loss"] = loss;
    }
    h["final"]["loss"] = h["iterations"].back()["loss"];
    h["final"]["parameters"] = h["iterations"].back()["parameters"];
    h["converged"] = true;
  });
  const std::string detail = FailedItem6(Judge(d, 1));
  EXPECT_NE(detail.find("rerun at the best parameters"), std::string::npos) << detail;
  EXPECT_NE(detail.find("does not reproduce"), std::string::npos) << detail;
}

TEST_F(Checklist, Item6FailsWhenTheBestParametersWereEdited) {
  const fs::path d = Copy("item6_parameters");
  EditJson(d / "fit/history.json", [](nlohmann::json& h) {
    nlohmann::json* best = &h["iterations"][0];
    for (auto& it : h["iterations"])
      if (it["loss"].get<double>() < (*best)["loss"].get<double>()) best = &it;
    for (auto& [name, value] : (*best)["parameters"].items()) value = value.get<double>() * 1.01;
    h["final"]["parameters"] = (*best)["parameters"];
  });
  const std::string detail = FailedItem6(Judge(d, 1));
  EXPECT_NE(detail.find("does not reproduce"), std::string::npos) << detail;
}

TEST_F(Checklist, Item6FailsWhenTheTargetsWereMoved) {
  const fs::path d = Copy("item6_targets");
  EditJson(d / "fit/history.json", [](nlohmann::json& h) {
    for (auto& t : h["targets"])
      if (t["metric"] != "rms") t["value"] = t["value"].get<double>() * 1.02;
  });
  const std::string detail = FailedItem6(Judge(d, 1));
  EXPECT_NE(detail.find("targets do not match the directory's reference"), std::string::npos)
      << detail;
}

// Weighted down, a target's residual shrinks until a bad fit converges; the scenario's manifest
// says what the weights are.
TEST_F(Checklist, Item6FailsWhenATargetIsWeightedOtherThanTheScenarioSays) {
  const fs::path d = Copy("item6_weights");
  EditJson(d / "fit/history.json", [](nlohmann::json& h) { h["targets"][1]["weight"] = 1e-6; });
  const std::string detail = FailedItem6(Judge(d, 1, "--scenario one_sprig"));
  EXPECT_NE(
      detail.find("targets are not the scenario's: target 2 is half_amplitude weighted 1e-06"),
      std::string::npos)
      << detail;
}

// The same with the caller's reference and manifest instead of a scenario's name: the manifest
// says what the weights are (it passed before).
TEST_F(Checklist, Item6HoldsTheTargetsToTheCallersManifest) {
  const fs::path d = Copy("item6_manifest_weights");
  const std::string manifest =
      " --manifest " + (fs::path(OWVAL_SOURCE_DIR) / "scenarios/manifests/one_sprig.json").string();
  EXPECT_EQ(Judge(d, 0, manifest)["verdict"], "ready");
  EditJson(d / "fit/history.json", [](nlohmann::json& h) { h["targets"][1]["weight"] = 1e-6; });
  const std::string detail = FailedItem6(Judge(d, 1, manifest));
  EXPECT_NE(
      detail.find("targets are not the scenario's: target 2 is half_amplitude weighted 1e-06"),
      std::string::npos)
      << detail;
}

// Without a scenario nothing names the weights: the period weighted 1e-6 reruns as recorded
// with a loss of 1.0e-7 and was ready. Judged with no weight below 1, its loss is 1.9e-3 again.
TEST_F(Checklist, Item6JudgesTheLossWithNoWeightBelowOne) {
  const fs::path d = Copy("item6_light_weight");
  ForgeFirstTargetAtIterationOne(d, [](nlohmann::json& period) {
    const double factor = std::sqrt(1e-6 / period["weight"].get<double>());
    period["weight"] = 1e-6;
    return factor;
  });
  const std::string detail = FailedItem6(Judge(d, 1));
  EXPECT_NE(detail.find("rerun at the best parameters"), std::string::npos) << detail;
  EXPECT_NE(detail.find("FAILS: the best loss with no weight below 1 is 0.0019"), std::string::npos)
      << detail;
}

// A residual is divided by its target's scale: -1000 times the period's passed "no larger than
// the value's magnitude" and the rerun at 1.0e-7 was ready, with the scenario named too.
TEST_F(Checklist, Item6FailsATargetWithANegativeScale) {
  const fs::path d = Copy("item6_negative_scale");
  ForgeFirstTargetAtIterationOne(d, [](nlohmann::json& period) {
    period["scale"] = -1000 * period["scale"].get<double>();
    return -1e-3;
  });
  const std::string detail = FailedItem6(Judge(d, 1, "--scenario one_sprig"));
  EXPECT_NE(detail.find("FAILS: target period's scale -0.72"), std::string::npos) << detail;
  EXPECT_NE(detail.find("is not positive"), std::string::npos) << detail;
}

// A history claiming a run longer than the reference its targets were measured on is not
// rerun (it would take as long as it claims).
TEST_F(Checklist, Item6DoesNotRerunAFitLongerThanTheReference) {
  const fs::path d = Copy("item6_longer");
  EditJson(d / "fit/history.json",
           [](nlohmann::json& h) { h["simulation"]["duration_s"] = 1000.0; });
  const std::string detail = FailedItem6(Judge(d, 1, "--scenario one_sprig"));
  EXPECT_NE(detail.find("not verified: the fit simulated 1000 s, longer than the directory's "
                        "reference"),
            std::string::npos)
      << detail;
}

TEST_F(Checklist, Item6FailsAsNotVerifiedWithoutTheSimulationRecord) {
  const fs::path d = Copy("item6_no_simulation");
  EditJson(d / "fit/history.json", [](nlohmann::json& h) { h.erase("simulation"); });
  const std::string detail = FailedItem6(Judge(d, 1));
  EXPECT_NE(detail.find("not verified: the history records no \"simulation\""), std::string::npos)
      << detail;
}

TEST_F(Checklist, Item6FailsAsNotVerifiedWhenTheConfigurationWasSwapped) {
  const fs::path d = Copy("item6_configuration");
  std::ofstream(d / "fit/configuration.txt", std::ios::app) << "\n";
  const std::string detail = FailedItem6(Judge(d, 1));
  EXPECT_NE(detail.find("not verified: configuration.txt is not the configuration the fit"),
            std::string::npos)
      << detail;
}

TEST_F(Checklist, Items7To9FailingLeaveItIncompleteButNotBlocking) {
  const fs::path d = Copy("items7to9");
  EditJson(d / "fd_tests.json", [](nlohmann::json& j) { j["tests"][0]["pass"] = false; });
  Write(d / "parameters.json", "{}");
  Write(d / "changes.md", "# Changes\n\n" + std::string(100000, ' ') + "\nno list here\n");
  const auto j = Judge(d, 0);
  EXPECT_EQ(j["verdict"], "incomplete but not blocking");
  for (int i : {7, 8, 9}) EXPECT_FALSE(ItemPasses(j, i)) << i;
  EXPECT_TRUE(ItemPasses(j, 10));
}

// fd_tests.json edited to say pass over a failing test: the test's own error against its own
// tolerance decides, and the item names the contradiction ("ready" before).
// parameters.json holds the fit's best parameters (fit/history.json's "final"), to 6 significant
// digits: {"viscosity": 42} beside a fit of the stiffness was ready before.
TEST_F(Checklist, Item8HoldsTheTunedValuesToTheFit) {
  const fs::path d = Copy("item8");
  const double best = nlohmann::json::parse(
      Slurp(d / "fit/history.json"))["final"]["parameters"]["elasticity_coefficient"];
  const auto item8 = [&](const nlohmann::json& parameters) {
    Write(d / "parameters.json", parameters.dump());
    const auto j = Judge(d, 0);
    return std::pair{ItemPasses(j, 8), j["items"][7]["detail"].get<std::string>()};
  };
  const auto [other_pass, other] = item8({{"viscosity", 42}});
  EXPECT_FALSE(other_pass);
  EXPECT_EQ(other, "1 tuned values; parameters.json lacks the fit's elasticity_coefficient");
  const auto [off_pass, off] = item8({{"parameters", {{"elasticity_coefficient", best * 1.01}}}});
  EXPECT_FALSE(off_pass);
  EXPECT_NE(off.find("elasticity_coefficient is "), std::string::npos) << off;
  char six_digits[32];
  std::snprintf(six_digits, sizeof six_digits, "%.6g", best);
  const auto [printed_pass, printed] =
      item8({{"elasticity_coefficient", std::stod(six_digits)}, {"viscosity", 42}});
  EXPECT_TRUE(printed_pass) << printed;
}

TEST_F(Checklist, Item7CountsATestThatSaysPassBeyondItsToleranceAsFailing) {
  const fs::path d = Copy("item7_claim");
  EditJson(d / "fd_tests.json", [](nlohmann::json& j) {
    j["tests"][0]["relative_error"] = 0.5;  // its tolerance is 0.02
    j["tests"][0]["pass"] = true;
  });
  const auto j = Judge(d, 0);
  EXPECT_EQ(j["verdict"], "incomplete but not blocking");
  EXPECT_FALSE(ItemPasses(j, 7));
  EXPECT_NE(
      j["items"][6]["detail"].get<std::string>().find("says pass, but its relative_error 0.5"),
      std::string::npos)
      << j["items"][6]["detail"];
}

TEST_F(Checklist, Item10ReconcilesThePredictionWithTheReference) {
  const fs::path d = Copy("item10");
  EditJson(d / "prediction.json", [](nlohmann::json& j) {
    for (auto& p : j["predictions"])
      if (p["quantity"] == "zero_crossing_period") p["value"] = p["value"].get<double>() * 1.2;
  });
  fs::remove(d / "reconcile.json");  // recomputed, not read
  const auto j = Judge(d, 0);
  EXPECT_FALSE(ItemPasses(j, 10));
  EXPECT_NE(j["items"][9]["detail"].get<std::string>().find("reference"), std::string::npos);
}

// A failing candidate (k = 3.3e8 against one_sprig's 1.62e8) with frames labelled on a wall
// particle that never moves: the checklist tracks the caller's quantity, not frames.json's.
TEST_F(Checklist, APullRequestCannotChooseTheTrackedParticle) {
  const fs::path d = Copy("chosen_track");
  ASSERT_NO_FATAL_FAILURE(ReplaceWithRun(d, kFailingCandidate, {"candidate.h5"}));
  ASSERT_NO_FATAL_FAILURE(Reframe(d, "--track-particle 1 --no-gate"));
  auto j = Judge(d, 1);
  EXPECT_EQ(j["verdict"], "not ready");
  EXPECT_FALSE(ItemPasses(j, 5));
  EXPECT_NE(j["items"][4]["detail"].get<std::string>().find("checklist tracks particle 0 y"),
            std::string::npos)
      << j["items"][4].dump();
  EXPECT_FALSE(j["parity"]["pass"].get<bool>());  // particle 0 y: the frames gate fails
  // Told by the caller to track the still particle, the parity gate is no evidence and fails.
  const fs::path manifest = Scratch() / "chosen_track_manifest.json";
  Write(manifest, R"({"track": {"particle": 1, "axis": "y"}})");
  j = Judge(d, 1, "--manifest " + manifest.string());
  EXPECT_EQ(j["verdict"], "not ready");
  EXPECT_NE(j["parity_note"].get<std::string>().find("does not move"), std::string::npos)
      << j["parity_note"];
}

// 5 ms of the same physics against the 50 ms reference: identical where they overlap, but the
// candidate covers a tenth of the reference.
TEST_F(Checklist, ACandidateThatCoversPartOfTheReferenceIsNotReady) {
  const fs::path d = Copy("short_candidate");
  ASSERT_NO_FATAL_FAILURE(ReplaceWithRun(d, "--time 0.005", {"candidate.h5"}));
  const auto j = Judge(d, 1);
  EXPECT_EQ(j["verdict"], "not ready");
  EXPECT_TRUE(ItemPasses(j, 5));  // frames 0, 15, 100 and 200 agree
  EXPECT_NE(j["blocking"].dump().find("window"), std::string::npos) << j["blocking"].dump();
}

// Reference and candidate both a k = 3.3e8 run: they agree with each other, but with
// --scenario the reference must be the scenario's own (here its bundled Sibernetic run).
TEST_F(Checklist, WithAScenarioTheReferenceMustBeTheScenarios) {
  EXPECT_EQ(Judge(Ready(), 0, "--scenario one_sprig")["verdict"], "ready");
  const fs::path d = Copy("own_reference");
  ASSERT_NO_FATAL_FAILURE(ReplaceWithRun(d, kFailingCandidate, {"reference.h5", "candidate.h5"}));
  ASSERT_NO_FATAL_FAILURE(Reframe(d));
  // Without the caller's reference, the report also repeats the file's own record.
  const auto own = JudgeAlone(d, 1);
  EXPECT_EQ(own["verdict"], "unreviewable");
  EXPECT_NE(own["items"][1]["detail"].get<std::string>().find("not reference-equivalent"),
            std::string::npos)
      << own["items"][1].dump();
  const auto j = Judge(d, 1, "--scenario one_sprig");
  EXPECT_EQ(j["verdict"], "unreviewable");
  EXPECT_FALSE(ItemPasses(j, 2));
  EXPECT_NE(
      j["items"][1]["detail"].get<std::string>().find("NOT the caller's reference (one_sprig's"),
      std::string::npos)
      << j["items"][1].dump();
}

// prediction.json's period 20% off with every tolerance loosened to 100%: it reconciles on its
// own terms, not on the scenario's.
TEST_F(Checklist, Item10TakesTheScenariosTolerancesWhenGivenAScenario) {
  const fs::path d = Copy("item10_loosened");
  EditJson(d / "prediction.json", [](nlohmann::json& j) {
    for (auto& p : j["predictions"]) {
      if (p["quantity"] == "zero_crossing_period") p["value"] = p["value"].get<double>() * 1.2;
      if (p["tolerance"].get<double>() > 0) p["tolerance"] = 1.0;
    }
  });
  EXPECT_TRUE(ItemPasses(Judge(d, 0), 10));
  const auto j = Judge(d, 0, "--scenario one_sprig");
  EXPECT_FALSE(ItemPasses(j, 10));
  EXPECT_NE(j["items"][9]["detail"].get<std::string>().find("the scenario's tolerances"),
            std::string::npos)
      << j["items"][9].dump();
}

TEST_F(Checklist, AStaleParityFileCannotMakeAFailingCandidateReady) {
  const fs::path d = Copy("stale_parity");
  ASSERT_NO_FATAL_FAILURE(ReplaceWithRun(d, kFailingCandidate, {"candidate.h5"}));
  const auto j = Judge(d, 1);  // parity.json from the ready run still says pass
  EXPECT_EQ(j["verdict"], "not ready");
  EXPECT_NE(j["parity_note"].get<std::string>().find("stale"), std::string::npos);
}

// Item 6 for fits of an external program (docs/checklist.md): `owval fit --fit-backend NAME`
// runs a registry entry's command, and the checklist reruns its best iterate only through the
// entry the caller names. The program here is owval itself, run as a process through the
// registry ({set:elasticity_coefficient}), as a port's would be: "mine" as fitted, "other" the
// same with gravity 9.0 m/s^2 instead of 9.8 (a program whose output differs).
class BackendFit : public Checklist {
 protected:
  // The caller's registry: both entries, in the test's own folder (never inside the directory
  // under review).
  static fs::path Registry(const fs::path& dir) {
    const std::string run = std::string(OWVAL_EXE) +
                            " --quiet run {config} --time {time} --log-step {log_step} "
                            "--no-fields --threads 1 "
                            "--set elasticity_coefficient={set:elasticity_coefficient}";
    fs::create_directories(dir);
    Write(dir / "backends.json",
          nlohmann::json{{"backends",
                          {{"mine", {{"command", run + " --out {out}"}}},
                           {"renamed", {{"command", run + " --out {out}"}}},
                           {"other", {{"command", run + " --set gravity_y=-9.0 --out {out}"}}}}}}
              .dump(2));
    return dir / "backends.json";
  }

  // The ready directory's fit made again through "mine": one_sprig for 0.02 s (within the
  // reference's 0.05 s), the ready fit's targets, made once per build under a file lock as
  // Ready() is (its own lock: flock would wait on the one Ready() holds).
  static fs::path Fitted() {
    const fs::path ready = Ready();
    const auto stamp = fs::last_write_time(OWVAL_EXE).time_since_epoch().count();
    const fs::path cache = fs::path(OWVAL_EXE).parent_path() / "test_cache";
    const fs::path d = cache / ("checklist_backend_fit_" + std::to_string(stamp));
    const int lock = ::open((cache / "checklist_backend_fit.lock").c_str(), O_CREAT | O_RDWR, 0600);
    ::flock(lock, LOCK_EX);
    if (!fs::exists(d / "complete")) {
      for (const fs::directory_entry& e : fs::directory_iterator(cache))
        if (e.path().filename().string().rfind("checklist_backend_fit_", 0) == 0) fs::remove_all(e);
      std::string targets;
      const nlohmann::json history = nlohmann::json::parse(Slurp(ready / "fit/history.json"));
      for (const auto& t : history["targets"])
        targets += " --target " + t["metric"].get<std::string>() + "=" + t["value"].dump() +
                   ":scale=" + t["scale"].dump() + ":weight=" + t["weight"].dump();
      const Result r = Owval("fit " + (ready / "fit/configuration.txt").string() + " --backends " +
                             Registry(d).string() +
                             " --fit-backend mine --param elasticity_coefficient=1.62e8:log "
                             "--time 0.02 -o " +
                             (d / "fit").string() + targets);
      EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
      if (r.exit_code == 0) std::ofstream(d / "complete") << "made by checklist_test\n";
    }
    ::flock(lock, LOCK_UN);
    ::close(lock);
    return d / "fit";
  }

  // A copy of the ready directory whose fit/ is the backend fit's.
  fs::path CopyWithBackendFit(const std::string& name) {
    const fs::path d = Copy(name), fit = Fitted();
    fs::remove_all(d / "fit");
    fs::copy(fit, d / "fit", fs::copy_options::recursive);
    return d;
  }

  // The checklist on d with the caller's registry (in the test's folder) and FLAGS.
  static nlohmann::json JudgeWith(const fs::path& d, int expected_exit, const std::string& flags) {
    return Judge(d, expected_exit,
                 "--backends " + Registry(Scratch() / "caller").string() + " " + flags);
  }

  static std::string Item6(const nlohmann::json& j) {
    return j["items"][5]["detail"].get<std::string>();
  }
};

TEST_F(BackendFit, TheFitRecordsTheBackendAndConverges) {
  const nlohmann::json h = nlohmann::json::parse(Slurp(Fitted() / "history.json"));
  EXPECT_TRUE(h["converged"].get<bool>()) << h["final"].dump();
  EXPECT_LT(h["final"]["loss"].get<double>(), 1e-4);
  const nlohmann::json& s = h["simulation"];
  EXPECT_EQ(s["kind"], "backend");
  EXPECT_EQ(s["name"], "mine");
  EXPECT_EQ(s["duration_s"], 0.02);
  EXPECT_EQ(s["log_step"], 1);
  EXPECT_EQ(s["time_step_s"], 2e-5);
  EXPECT_EQ(s["configuration"]["file"], "configuration.txt");
  EXPECT_TRUE(fs::is_regular_file(Fitted() / "configuration.txt"));
}

TEST_F(BackendFit, Item6RerunsItThroughTheCallersEntryAndItIsReady) {
  const fs::path d = CopyWithBackendFit("backend_ready");
  const auto j = JudgeWith(d, 0, "--fit-backend mine");
  EXPECT_EQ(j["verdict"], "ready");
  EXPECT_TRUE(ItemPasses(j, 6)) << Item6(j);
  EXPECT_NE(Item6(j).find("rerun at the best parameters (backend mine of the caller's"),
            std::string::npos)
      << Item6(j);
  EXPECT_NE(Item6(j).find("(tolerance 1e-09 relative)"), std::string::npos) << Item6(j);
  EXPECT_NE(Item6(j).find("with no weight below 1"), std::string::npos) << Item6(j);
  EXPECT_EQ(Item6(j).find("the history fitted"), std::string::npos) << Item6(j);
}

// The reviewer's registry may name the port otherwise: the rerun is judged as any other, and the
// report says the names differ (it may also be a rerun through another substrate).
TEST_F(BackendFit, Item6SaysWhenTheCallersEntryHasAnotherName) {
  const fs::path d = CopyWithBackendFit("backend_renamed");
  const auto j = JudgeWith(d, 0, "--fit-backend renamed");
  EXPECT_TRUE(ItemPasses(j, 6)) << Item6(j);
  EXPECT_NE(Item6(j).find("(backend renamed of the caller's"), std::string::npos) << Item6(j);
  EXPECT_NE(Item6(j).find("(the history fitted backend 'mine')"), std::string::npos) << Item6(j);
}

TEST_F(BackendFit, Item6IsNotVerifiedWithoutTheCallersEntry) {
  const fs::path d = CopyWithBackendFit("backend_no_entry");
  const std::string detail = FailedItem6(Judge(d, 1));
  EXPECT_NE(detail.find("not verified: a fit of backend 'mine' is rerun only through the "
                        "reviewer's own registry entry"),
            std::string::npos)
      << detail;
}

TEST_F(BackendFit, Item6FailsThroughAProgramWhoseOutputDiffers) {
  const fs::path d = CopyWithBackendFit("backend_other");
  const std::string detail = FailedItem6(JudgeWith(d, 1, "--fit-backend other"));
  EXPECT_NE(detail.find("FAILS: the rerun does not reproduce"), std::string::npos) << detail;
}

TEST_F(BackendFit, Item6FailsWhenTheBestParametersWereEdited) {
  const fs::path d = CopyWithBackendFit("backend_parameters");
  EditJson(d / "fit/history.json", [](nlohmann::json& h) {
    nlohmann::json* best = nullptr;
    for (auto& it : h["iterations"])
      if (it["parameters"] == h["final"]["parameters"]) best = &it;
    ASSERT_NE(best, nullptr);
    const double k = h["final"]["parameters"]["elasticity_coefficient"].get<double>() * 1.01;
    (*best)["parameters"]["elasticity_coefficient"] = k;
    h["final"]["parameters"]["elasticity_coefficient"] = k;
  });
  const std::string detail = FailedItem6(JudgeWith(d, 1, "--fit-backend mine"));
  EXPECT_NE(detail.find("FAILS: the rerun does not reproduce"), std::string::npos) << detail;
}

// One residual moved by 1e-6 and the losses made to agree: self-consistent, and rerun, wrong.
TEST_F(BackendFit, Item6FailsWhenAResidualWasEdited) {
  const fs::path d = CopyWithBackendFit("backend_residual");
  EditJson(d / "fit/history.json", [](nlohmann::json& h) {
    for (auto& it : h["iterations"]) {
      if (it["parameters"] != h["final"]["parameters"]) continue;
      it["residuals"][0] = it["residuals"][0].get<double>() + 1e-6;
      double loss = 0;
      for (const auto& r : it["residuals"]) loss += r.get<double>() * r.get<double>();
      it["loss"] = loss;
      h["final"]["loss"] = loss;
    }
  });
  const std::string detail = FailedItem6(JudgeWith(d, 1, "--fit-backend mine"));
  EXPECT_EQ(detail.find("CONTRADICTED"), std::string::npos) << detail;
  EXPECT_NE(detail.find("FAILS: the rerun does not reproduce"), std::string::npos) << detail;
}

TEST_F(BackendFit, Item6IsNotVerifiedWhenTheConfigurationWasSwapped) {
  const fs::path d = CopyWithBackendFit("backend_configuration");
  std::ofstream(d / "fit/configuration.txt", std::ios::app) << "\n";
  const std::string detail = FailedItem6(JudgeWith(d, 1, "--fit-backend mine"));
  EXPECT_NE(detail.find("not verified: configuration.txt is not the configuration the fit"),
            std::string::npos)
      << detail;
}

// Its targets are measured on the directory's 0.05 s reference: a claimed 1000 s is another fit,
// and rerunning it would run the caller's program for as long; refused before any run.
TEST_F(BackendFit, Item6DoesNotRerunARunLongerThanTheReference) {
  const fs::path d = CopyWithBackendFit("backend_longer");
  EditJson(d / "fit/history.json",
           [](nlohmann::json& h) { h["simulation"]["duration_s"] = 1000.0; });
  const std::string detail = FailedItem6(JudgeWith(d, 1, "--fit-backend mine"));
  EXPECT_NE(detail.find("not verified: the fit simulated 1000 s, longer than the directory's "
                        "reference"),
            std::string::npos)
      << detail;
  EXPECT_EQ(detail.find("rerun at the best parameters"), std::string::npos) << detail;
}

TEST_F(BackendFit, ALooserRerunToleranceIsTheCallersAndIsReported) {
  const fs::path d = CopyWithBackendFit("backend_tolerance");
  const auto j = JudgeWith(d, 0, "--fit-backend mine --fit-rerun-tolerance 1e-6");
  EXPECT_TRUE(ItemPasses(j, 6)) << Item6(j);
  EXPECT_NE(Item6(j).find("(tolerance 1e-06 relative)"), std::string::npos) << Item6(j);
  // Named beside the loosened gates, with what the rerun gives at DD001's 1e-9.
  EXPECT_EQ(j["loosened_fit_rerun"],
            "fit_rerun_tolerance 1e-06 (caller; default 1e-09): the rerun reproduces the best "
            "iteration at the default too");
  EXPECT_EQ(JudgeWith(d, 0, "--fit-backend mine")["loosened_fit_rerun"], "");
}

// A best iteration whose residuals the rerun reproduces to 1e-7 relative, not to 1e-9: item 6
// passes at the caller's 1e-6, and the report says it would not at the default.
TEST_F(BackendFit, ALooserRerunToleranceSaysWhatTheDefaultWouldFind) {
  const fs::path d = CopyWithBackendFit("backend_tolerance_needed");
  EditJson(d / "fit/history.json", [](nlohmann::json& h) {
    for (auto& it : h["iterations"]) {
      if (it["parameters"] != h["final"]["parameters"]) continue;
      it["residuals"][0] = it["residuals"][0].get<double>() * (1 + 1e-7);
      double loss = 0;
      for (const auto& r : it["residuals"]) loss += r.get<double>() * r.get<double>();
      it["loss"] = loss;
      h["final"]["loss"] = loss;
    }
  });
  const auto j = JudgeWith(d, 0, "--fit-backend mine --fit-rerun-tolerance 1e-6");
  EXPECT_TRUE(ItemPasses(j, 6)) << Item6(j);
  EXPECT_EQ(j["loosened_fit_rerun"],
            "fit_rerun_tolerance 1e-06 (caller; default 1e-09): at the default the rerun does NOT "
            "reproduce the best iteration's residuals");
  FailedItem6(JudgeWith(d, 1, "--fit-backend mine"));
}

// Bad input: one line, exit 2, no report.
TEST_F(BackendFit, AnUnknownEntryOrAMissingOrReviewedRegistryIsBadInput) {
  const fs::path d = CopyWithBackendFit("backend_bad_input");
  const std::string reference = " --reference " + (Ready() / "reference.h5").string();
  const fs::path registry = Registry(Scratch() / "caller");
  for (const std::string& flags :
       {"--backends " + registry.string() + " --fit-backend nosuch",
        "--backends " + (Scratch() / "missing.json").string() + " --fit-backend mine",
        "--backends " + (d / "fit/backends.json").string() + " --fit-backend mine"}) {
    if (flags.find(d.string()) != std::string::npos)
      fs::copy_file(registry, d / "fit/backends.json");
    const Result r = Owval("checklist " + d.string() + reference + " --json " + flags);
    EXPECT_EQ(r.exit_code, 2) << flags << "\n" << r.out << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
}

TEST_F(BackendFit, TheFitRefusesAnEntryItCannotFitAndLeavesNothing) {
  const fs::path registry = Registry(Scratch() / "caller"), out = Scratch() / "refused";
  const std::string config = (Ready() / "fit/configuration.txt").string();
  for (const std::string& flags :
       {std::string(" --fit-backend nosuch --param elasticity_coefficient=1.62e8:log"),
        std::string(" --fit-backend owval --param elasticity_coefficient=1.62e8:log"),
        std::string(" --fit-backend mine --param gravity_y=-9.8"),
        // --backend names an engine scheme, which a named backend's fit never runs: a fit
        // recorded as xpbd's that ran "mine" would mislead.
        std::string(" --fit-backend mine --backend xpbd --param elasticity_coefficient=1.62e8:log"),
        std::string(" --command 'true {out}' --backend xpbd --param k=1")}) {
    const Result r = Owval("fit " + config + " --backends " + registry.string() + flags +
                           " --target period=7.246e-4 -o " + out.string());
    EXPECT_EQ(r.exit_code, 2) << flags << "\n" << r.out << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(out)) << flags;
  }
}

}  // namespace
}  // namespace owval::testing
