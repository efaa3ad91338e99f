// sgd/backend_simulator.hpp at the library level: a named command backend as a fit's simulator,
// with a real external process (/bin/sh running cp) whose output depends on the parameter's
// text, so each test sees what the command received. The end-to-end fit and checklist rerun
// through `owval run` are cli/tests/checklist_test.cpp's BackendFit tests.
#include "owval/sgd/backend_simulator.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "owval/base/errors.hpp"
#include "owval/testing/scratch_directory.hpp"
#include "owval/trajectory/formats.hpp"

namespace owval::sgd {
namespace {
namespace fs = std::filesystem;

// One moving particle whose y is `y_cu` at both frames (0 and 2e-5 s).
void WriteRun(const fs::path& path, float y_cu) {
  Trajectory t;
  t.box = {0, 10, 0, 10, 0, 10};
  t.time_step_s = 2e-5;
  t.type = {2.1f};
  const float position[3] = {1, y_cu, 1};
  t.AppendFrame(0, position);
  t.AppendFrame(2e-5, position);
  WriteHdf5(t, path);
}

class BackendSimulatorTest : public ::testing::Test {
 protected:
  void SetUp() override {
    // One recorded run per parameter text the command may receive: 0.25 exactly, and 0.1 as 17
    // significant digits (what gives the double back).
    WriteRun(scratch_.path() / "run_0.25.h5", 3.0f);
    WriteRun(scratch_.path() / "run_0.10000000000000001.h5", 7.0f);
    backend_.name = "copier";
    backend_.kind = backends::BackendKind::kCommand;
    // It also notes each run's {out} directory, so a test can see it removed afterwards.
    backend_.command = "cp " + scratch_.path().string() +
                       "/run_{set:k}.h5 {out}/trajectory.h5 && echo {out} >> " +
                       (scratch_.path() / "outs.txt").string();
    backend_.output = "{out}/trajectory.h5";
    backend_.layout = "hdf5";
    backend_.defined_in = "backend_simulator_test";
    run_.configuration = scratch_.path() / "configuration";  // {config}: cp never reads it
    std::ofstream(run_.configuration) << "not read\n";
    run_.duration_s = 2e-5;
  }

  TrackedSeries Run(double k) {
    return RunBackendTrackedSeries(backend_, run_, {"k"}, {k}, Track{});
  }

  owval::testing::ScratchDirectory scratch_{"backend_simulator"};
  backends::Backend backend_;
  BackendRun run_;
};

TEST_F(BackendSimulatorTest, TheParameterReachesTheCommandWithSeventeenDigits) {
  const TrackedSeries a = Run(0.25), b = Run(0.1);
  ASSERT_EQ(a.frame_count(), 2u);
  EXPECT_EQ(a.value, (std::vector<double>{3.0, 3.0}));
  EXPECT_EQ(a.time_s, (std::vector<double>{0, 2e-5}));
  EXPECT_EQ(b.value, (std::vector<double>{7.0, 7.0}));
}

TEST_F(BackendSimulatorTest, AValueTheCommandCannotAnswerIsBadInputNamingTheBackend) {
  try {
    Run(0.5);  // no run_0.5.h5: cp fails
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("copier"), std::string::npos) << e.what();
  }
}

TEST_F(BackendSimulatorTest, EachRunsDirectoryIsRemovedOnceTheSeriesIsRead) {
  Run(0.25);
  Run(0.1);
  std::ifstream outs(scratch_.path() / "outs.txt");
  std::vector<std::string> directories;
  for (std::string line; std::getline(outs, line);) directories.push_back(line);
  ASSERT_EQ(directories.size(), 2u);
  EXPECT_NE(directories[0], directories[1]);  // each evaluation in a directory of its own
  for (const std::string& d : directories) EXPECT_FALSE(fs::exists(d)) << d;
}

TEST_F(BackendSimulatorTest, OnlyACommandNamingEveryParameterCanBeFitted) {
  EXPECT_NO_THROW(CheckFittableBackend(backend_, {"k"}));
  EXPECT_THROW(CheckFittableBackend(backend_, {"k", "viscosity"}), InputError);
  EXPECT_THROW(BackendSimulator(backend_, run_, {Parameter{"viscosity"}}), InputError);
  backends::Backend builtin;
  builtin.name = "owval";
  EXPECT_THROW(CheckFittableBackend(builtin, {"k"}), InputError);
}

TEST_F(BackendSimulatorTest, TheSimulatorRunsTheCommandPerEvaluation) {
  Parameter k;
  k.name = "k";
  const Simulator simulate = BackendSimulator(backend_, run_, {k});
  EXPECT_EQ(simulate({0.25}, Track{}).value.front(), 3.0);
  EXPECT_EQ(simulate({0.1}, Track{}).value.front(), 7.0);
}

TEST_F(BackendSimulatorTest, TheHistoryRecordsTheBackendAndTheRun) {
  const nlohmann::json j = BackendSimulationJson(backend_, run_, {{"file", "configuration.txt"}});
  EXPECT_EQ(j["kind"], "backend");
  EXPECT_EQ(j["name"], "copier");
  EXPECT_EQ(j["command"], backend_.command);
  EXPECT_EQ(j["duration_s"], 2e-5);
  EXPECT_EQ(j["time_step_s"], 2e-5);
  EXPECT_EQ(j["log_step"], 1);
  EXPECT_EQ(j["configuration"]["file"], "configuration.txt");
}

}  // namespace
}  // namespace owval::sgd
