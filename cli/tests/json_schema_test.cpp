// owval's machine-readable outputs against their published JSON Schemas (docs/schemas/, draft
// 2020-12): each document is made by the real command on built-in data and validated with
// python3-jsonschema (check_json_schema.py); each family also has an edited copy (a required key
// removed, a type or a pinned value changed) that the schema must reject, so that a test here can
// fail. A renamed key, a changed type or a new key the schema does not list fails the check.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_support.hpp"
#include "owval/testing/test_files.hpp"

namespace owval::testing {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

const fs::path kPython = "/usr/bin/python3";  // Debian's, where python3-jsonschema lives
const fs::path kChecker = fs::path(OWVAL_SOURCE_DIR) / "cli/tests/check_json_schema.py";
const fs::path kSchemas = fs::path(OWVAL_SOURCE_DIR) / "docs/schemas";

// check_json_schema.py's verdict on FILE against docs/schemas/NAME.schema.json.
Result Check(const std::string& name, const fs::path& file) {
  return RunCaptured(kPython.string() + " " + kChecker.string() + " " +
                     (kSchemas / (name + ".schema.json")).string() + " " + file.string());
}

void ExpectValid(const std::string& name, const fs::path& file) {
  const Result r = Check(name, file);
  EXPECT_EQ(r.exit_code, 0) << name << " " << file << ":\n" << r.out << r.err;
  EXPECT_EQ(r.out, "valid: " + name + ".schema.json\n") << r.out;
}

// The edited copy of FILE is rejected (exit 1), the violation naming `where` (a JSON path).
void ExpectRejected(const std::string& name, const fs::path& file, const std::string& where,
                    const std::function<void(json&)>& edit) {
  json j = json::parse(Slurp(file));
  edit(j);
  // In the test's own directory: FILE may be in the ready directory other tests share.
  const fs::path edited = Scratch() / ("edited_" + file.filename().string());
  std::ofstream(edited) << j.dump(2);
  const Result r = Check(name, edited);
  EXPECT_EQ(r.exit_code, 1) << name << " accepted an edited " << file << ":\n" << r.out << r.err;
  EXPECT_EQ(r.out.rfind(where, 0), 0u) << name << ": " << r.out;
}

// `owval --quiet ARGS`'s stdout in the test's scratch directory as NAME (the command must exit 0).
fs::path StdoutOf(const std::string& args, const std::string& name) {
  const Result r = Owval(args);
  EXPECT_EQ(r.exit_code, 0) << args << ": " << r.err;
  const fs::path file = Scratch() / name;
  std::ofstream(file) << r.out;
  return file;
}

bool CheckerMissing() { return !fs::exists(kPython); }

TEST(JsonSchema, PredictionAndReconciliationOfOneSprig) {
  if (CheckerMissing()) GTEST_SKIP() << "needs python3 with python3-jsonschema";
  const fs::path prediction = StdoutOf("predict one_sprig --json", "prediction.json");
  ExpectValid("prediction", prediction);
  ExpectRejected("prediction", prediction, "$: 'predictions' is a required property",
                 [](json& j) { j.erase("predictions"); });
  ExpectRejected("prediction", prediction,
                 "$.schema:", [](json& j) { j["schema"] = "owval.prediction/2"; });
  const fs::path reconcile =
      StdoutOf("reconcile " + prediction.string() + " " + kBundledOneSprig.string() + " --json",
               "reconcile.json");
  ExpectValid("reconcile", reconcile);
  ExpectRejected("reconcile", reconcile,
                 "$.rows[0].pass:", [](json& j) { j["rows"][0]["pass"] = "true"; });
}

// The per-bead and per-layer tables a prediction carries beside a quantity ("beads", "profile").
TEST(JsonSchema, PredictionsWithTheirTables) {
  if (CheckerMissing()) GTEST_SKIP() << "needs python3 with python3-jsonschema";
  for (const auto& [scenario, table] :
       {std::pair<std::string, std::string>{"hanging_chain", "beads"},
        {"liquid_column", "profile"}}) {
    const fs::path file = StdoutOf("predict " + scenario + " --json", scenario + ".json");
    ASSERT_NE(Slurp(file).find("\"" + table + "\""), std::string::npos) << scenario;
    ExpectValid("prediction", file);
    ExpectRejected("prediction", file, "$.predictions[", [&table = table](json& j) {
      for (json& q : j["predictions"])
        if (q.contains(table)) q[table] = "a table";
    });
  }
}

TEST(JsonSchema, CompareOfTheBundledRunWithItself) {
  if (CheckerMissing()) GTEST_SKIP() << "needs python3 with python3-jsonschema";
  const std::string run = kBundledOneSprig.string();
  const fs::path report = StdoutOf("compare " + run + " " + run + " --json", "compare.json");
  ExpectValid("parity", report);
  ExpectRejected("parity", report, "$.gates[0]: 'status' is a required property",
                 [](json& j) { j["gates"][0].erase("status"); });
  ExpectRejected("parity", report, "$.reference_metrics.samples:", [](json& j) {
    j["reference_metrics"]["samples"] = 2.5;
  });
}

TEST(JsonSchema, RunSummaryWithAndWithoutStability) {
  if (CheckerMissing()) GTEST_SKIP() << "needs python3 with python3-jsonschema";
  const std::string out = (Scratch() / "run").string();
  const fs::path plain = StdoutOf("run one_sprig --time 0.01 --json -o " + out, "run.json");
  ExpectValid("run_summary", plain);
  ExpectRejected("run_summary", plain, "$.steps:", [](json& j) { j["steps"] = "500"; });
  const fs::path stable =
      StdoutOf("run one_sprig --time 0.01 --stability --json -o " + out + "_stability",
               "run_stability.json");
  ASSERT_TRUE(json::parse(Slurp(stable)).contains("stability"));
  ExpectValid("run_summary", stable);
  ExpectRejected("run_summary", stable, "$.stability: 'non_finite' is a required property",
                 [](json& j) { j["stability"].erase("non_finite"); });
}

TEST(JsonSchema, GradcheckFdTests) {
  if (CheckerMissing()) GTEST_SKIP() << "needs python3 with python3-jsonschema";
  const fs::path file = Scratch() / "fd_tests.json";
  ASSERT_EQ(Owval("gradcheck sph_density -o " + file.string()).exit_code, 0);
  ExpectValid("fd_tests", file);
  ExpectRejected("fd_tests", file, "$.tests[0]", [](json& j) { j["tests"][0].erase("analytic"); });
}

TEST(JsonSchema, ScenarioList) {
  if (CheckerMissing()) GTEST_SKIP() << "needs python3 with python3-jsonschema";
  const fs::path list = StdoutOf("scenario list --json", "scenarios.json");
  ASSERT_GE(json::parse(Slurp(list)).size(), 1u);
  ExpectValid("scenario_list", list);
  ExpectRejected("scenario_list", list, "$[0]: 'name' is a required property",
                 [](json& j) { j[0]["scenario"] = j[0]["name"], j[0].erase("name"); });
}

// A finite-difference fit of the engine (0.005 s of one_sprig) and an analytic-gradient XPBD fit
// (30 steps against the bundled run): the two shapes history.json takes.
TEST(JsonSchema, FitHistoriesOfBothKinds) {
  if (CheckerMissing()) GTEST_SKIP() << "needs python3 with python3-jsonschema";
  const fs::path fd = Scratch() / "fit_fd", analytic = Scratch() / "fit_analytic";
  ASSERT_EQ(Owval("fit one_sprig --param elasticity_coefficient=1.62e8:log --target "
                  "period=0.7246e-3:scale=0.725e-3 --time 0.005 -o " +
                  fd.string())
                .exit_code,
            0);
  ASSERT_EQ(Owval("fit one_sprig --param elasticity_coefficient=2e8:log --gradient analytic "
                  "--reference " +
                  kBundledOneSprig.string() +
                  " --time 0.0006 --threshold 1e3 --max-iterations 2 -o " + analytic.string())
                .exit_code,
            0);
  ExpectValid("fit_history", fd / "history.json");
  ExpectValid("fit_history", analytic / "history.json");
  ExpectRejected("fit_history", fd / "history.json", "$: 'simulation' is a required property",
                 [](json& j) { j.erase("simulation"); });
  ExpectRejected("fit_history", analytic / "history.json", "$: 'reverse' is a required property",
                 [](json& j) { j.erase("reverse"); });
  ExpectRejected("fit_history", fd / "history.json", "$.targets[0].track.axis:", [](json& j) {
    j["targets"][0]["track"]["axis"] = "w";
  });
}

// The gates' other figures: the streamed stability gate (ci validate --stability: the report and
// its steps) and the candidate's incompressibility (a liquid run as both reference and candidate).
TEST(JsonSchema, StreamedStabilityAndIncompressibilityGates) {
  if (CheckerMissing()) GTEST_SKIP() << "needs python3 with python3-jsonschema";
  const fs::path streamed =
      StdoutOf("ci validate --stability 10ms --scenario one_sprig --json -o " +
                   (Scratch() / "stability").string(),
               "streamed.json");
  ExpectValid("gates", streamed);
  ExpectRejected("gates", streamed, "$.gates[0].measured",
                 [](json& j) { j["gates"][0]["measured"].erase("steps"); });
  const fs::path d = Scratch() / "liquid", run = Scratch() / "liquid_run";
  ASSERT_EQ(Owval("run liquid_column --time 0.002 -o " + run.string()).exit_code, 0);
  fs::create_directories(d);
  for (const char* side : {"reference.h5", "candidate.h5"})
    fs::copy_file(run / "trajectory.h5", d / side);
  // Exit 1 or 0 alike: the document's shape is under test, not the liquid's verdict.
  const Result r =
      Owval("ci validate " + d.string() + " --json --reference " + (d / "reference.h5").string());
  ASSERT_TRUE(r.exit_code == 0 || r.exit_code == 1) << r.exit_code << ": " << r.err;
  const fs::path validate = Scratch() / "liquid_validate.json";
  std::ofstream(validate) << r.out;
  ASSERT_NE(r.out.find("\"candidate incompressibility\""), std::string::npos) << r.out;
  ExpectValid("gates", validate);
  ExpectRejected("gates", validate, "$.gates[", [](json& j) {
    for (json& g : j["gates"])
      if (g["name"] == "candidate incompressibility") g["measured"].erase("worst_frame");
  });
}

// The checklist and the CI gates over the ready pipeline directory, and the documents the
// pipeline wrote there (its fd_tests.json is the engine's period test, not gradcheck's).
TEST(JsonSchema, ChecklistGatesAndThePipelinesFiles) {
  if (CheckerMissing()) GTEST_SKIP() << "needs python3 with python3-jsonschema";
  const fs::path d = ReadyPipelineDirectory();
  const std::string reference = " --reference " + (d / "reference.h5").string();
  const fs::path checklist =
      StdoutOf("checklist " + d.string() + " --json" + reference, "checklist.json");
  ExpectValid("checklist", checklist);
  ExpectRejected("checklist", checklist, "$.parity.gates[0].status:", [](json& j) {
    j["parity"]["gates"][0]["status"] = "passed";
  });
  ExpectRejected("checklist", checklist, "$.verdict:", [](json& j) { j["verdict"] = "READY"; });
  const fs::path quick = StdoutOf("ci quick-test " + d.string() + " --json", "quick.json");
  ExpectValid("gates", quick);
  const fs::path validate =
      StdoutOf("ci validate " + d.string() + " --json" + reference, "validate.json");
  ExpectValid("gates", validate);
  ExpectRejected("gates", validate, "$.gates[0]: 'pass' is a required property",
                 [](json& j) { j["gates"][0].erase("pass"); });
  ExpectRejected("gates", validate, "$.gates[", [](json& j) {
    for (json& g : j["gates"])  // the parity gate counts its failing frames, it does not list them
      if (g["name"] == "parity") g["measured"]["failing_frame_count"] = json::array();
  });
  for (const auto& [name, file] :
       {std::pair<std::string, std::string>{"prediction", "prediction.json"},
        {"reconcile", "reconcile.json"},
        {"parity", "parity.json"},
        {"checklist", "checklist.json"},
        {"fit_history", "fit/history.json"},
        {"fd_tests", "fd_tests.json"}})
    ExpectValid(name, d / file);
  ExpectRejected("fd_tests", d / "fd_tests.json", "$.tests[0]",
                 [](json& j) { j["tests"][0].erase("tolerance"); });
}

}  // namespace
}  // namespace owval::testing
