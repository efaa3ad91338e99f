// What `owval run` says and exits with once a run returns (pipeline::RunDirectorySummary).
#include <gtest/gtest.h>

#include <csignal>
#include <string>

#include "owval/pipeline/run_directory.hpp"

namespace owval::pipeline {
namespace {

RunDirectorySummary Interrupted(const std::string& out, bool checkpointed) {
  RunDirectorySummary s;
  s.out = out;
  s.backend = "wcsph";
  s.run.steps = 120;
  s.run.interrupted = true;
  s.run.checkpointed = checkpointed;
  return s;
}

TEST(RunDirectorySummary, ACompleteRunPassesWithNothingToSay) {
  RunDirectorySummary s;
  s.out = "out";
  s.run.first_step = 0, s.run.steps = 200, s.run.frames = 11;
  EXPECT_EQ(s.FailureLine(), "");
  EXPECT_EQ(s.exit_code(0), 0);
  EXPECT_NE(s.ToText().find("ran steps 0 to 200 in "), std::string::npos) << s.ToText();
  EXPECT_NE(s.ToText().find("11 frames -> out\n"), std::string::npos) << s.ToText();
}

TEST(RunDirectorySummary, AnInterruptedRunNamesTheResumeCommandWithTheDirectoryQuoted) {
  const RunDirectorySummary s = Interrupted("my run", true);
  EXPECT_EQ(s.FailureLine().rfind("interrupted after step 120: partial trajectory in my run", 0),
            0u);
  EXPECT_NE(s.FailureLine().find("continue with: owval run --resume 'my run'"), std::string::npos)
      << s.FailureLine();
  EXPECT_EQ(s.exit_code(SIGINT), 130);
  EXPECT_EQ(s.exit_code(SIGTERM), 143);
}

TEST(RunDirectorySummary, ABackendWithoutCheckpointsSaysThereIsNoResume) {
  const RunDirectorySummary s = Interrupted("out", false);
  EXPECT_EQ(s.FailureLine(),
            "interrupted after step 120: partial trajectory in out (backend wcsph cannot "
            "checkpoint: no --resume)");
}

}  // namespace
}  // namespace owval::pipeline
