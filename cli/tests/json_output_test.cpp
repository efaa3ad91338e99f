// `--json` wherever a person would otherwise parse text: the CI gates, the pipeline's summary and
// the scenario list print what their text says, as JSON, with the same exit codes.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "owval/testing/test_files.hpp"

namespace owval::testing {
namespace {
namespace fs = std::filesystem;

// An artifact directory: the bundled one_sprig reference and, as candidate, owval's run of it
// (which reproduces the reference) with `set` ("--set elasticity_coefficient=3.3e8" fails parity).
fs::path ArtifactDirectory(const std::string& name, const std::string& set) {
  const fs::path dir = Scratch() / name;
  fs::create_directories(dir);
  fs::copy_file(kOneSprig, dir / "reference.txt", fs::copy_options::overwrite_existing);
  const Result run = Owval("run one_sprig --no-fields --out " + (dir / "run").string() + " " + set);
  EXPECT_EQ(run.exit_code, 0) << run.err;
  fs::rename(dir / "run/trajectory.h5", dir / "candidate.h5");
  fs::remove_all(dir / "run");
  return dir;
}

TEST(JsonOutput, CiGatesSayInJsonWhatTheirTextSaysWithTheSameExitCode) {
  const fs::path dir = ArtifactDirectory("stiff", "--set elasticity_coefficient=3.3e8");
  const std::string validate = "ci validate " + dir.string() + " --reference " + kOneSprig;
  const Result text = Owval(validate), json = Owval(validate + " --json");
  EXPECT_EQ(text.exit_code, 1) << text.out << text.err;
  EXPECT_EQ(json.exit_code, 1) << json.err;
  const nlohmann::json report = nlohmann::json::parse(json.out);
  EXPECT_FALSE(report["pass"].get<bool>());
  ASSERT_EQ(report["gates"].size(), 6u)
      << json.out;  // caller's, 2 x (stability, completed), parity
  // Each gate's line of the text, from the JSON's name, verdict and detail.
  for (const nlohmann::json& g : report["gates"]) {
    const std::string line = std::string(g["pass"].get<bool>() ? "PASS " : "FAIL ") +
                             g["name"].get<std::string>() + ": " + g["detail"].get<std::string>() +
                             "\n";
    EXPECT_NE(text.out.find(line), std::string::npos) << line << text.out;
  }
  // The figures as data: the parity gate's own gates, the stability report's fields.
  const nlohmann::json* parity = GateNamed(report, "parity");
  ASSERT_NE(parity, nullptr);
  EXPECT_FALSE((*parity)["pass"].get<bool>());
  bool frames_failed = false;
  for (const nlohmann::json& g : (*parity)["measured"]["gates"])
    frames_failed |= g["name"] == "frames" && g["status"] == "FAIL";
  EXPECT_TRUE(frames_failed) << parity->dump();
  EXPECT_GT((*parity)["measured"]["failing_frame_count"].get<std::size_t>(), 0u);
  const nlohmann::json* stability = GateNamed(report, "candidate stability");
  ASSERT_NE(stability, nullptr);
  EXPECT_TRUE((*stability)["measured"]["pass"].get<bool>()) << stability->dump();
  EXPECT_EQ((*stability)["measured"]["frames"], 2500);

  const Result quick = Owval("ci quick-test " + dir.string() + " --json");
  EXPECT_EQ(quick.exit_code, 0) << quick.err;
  const nlohmann::json completed = nlohmann::json::parse(quick.out);
  EXPECT_TRUE(completed["pass"].get<bool>());
  EXPECT_EQ(completed["gates"].size(), 2u) << quick.out;
}

TEST(JsonOutput, AReproducingCandidatePassesValidateInJson) {
  const fs::path dir = ArtifactDirectory("owval", "");
  const Result r = Owval("ci validate " + dir.string() + " --reference " + kOneSprig + " --json");
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_TRUE(nlohmann::json::parse(r.out)["pass"].get<bool>()) << r.out;
}

TEST(JsonOutput, PipelineSummaryNamesEveryPhaseAndTheChecklistVerdict) {
  const fs::path dir = Scratch() / "free_fall";
  const Result r = Owval("pipeline free_fall --max-video-frames 10 --json -o " + dir.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json summary = nlohmann::json::parse(r.out);
  EXPECT_EQ(summary["exit_code"], 0);
  EXPECT_EQ(summary["report"], (dir / "index.html").string());
  EXPECT_TRUE(fs::exists(summary["report"].get<std::string>()));
  std::vector<std::string> phases;
  for (const nlohmann::json& p : summary["phases"]) phases.push_back(p["name"]);
  EXPECT_EQ(phases.front(), "1 predict");
  EXPECT_EQ(phases.back(), "8 checklist");
  EXPECT_EQ(summary["checklist"]["verdict"],
            nlohmann::json::parse(Slurp(dir / "checklist.json"))["verdict"]);
  EXPECT_EQ(summary["parity"]["pass"], true);
}

TEST(JsonOutput, ScenarioListInJsonIsTheTextsNamesAndDescriptions) {
  const Result text = Owval("scenario list"), json = Owval("scenario list --json");
  ASSERT_EQ(text.exit_code, 0);
  ASSERT_EQ(json.exit_code, 0) << json.err;
  std::string lines;
  for (const nlohmann::json& s : nlohmann::json::parse(json.out))
    lines += s["name"].get<std::string>() + "\t" + s["description"].get<std::string>() + "\n";
  EXPECT_EQ(lines, text.out);
  EXPECT_NE(lines.find("one_sprig\t"), std::string::npos);
}

}  // namespace
}  // namespace owval::testing
