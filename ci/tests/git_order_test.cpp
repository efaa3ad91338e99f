// Item 1's order in the git history (PredictionCommittedFirst) on small repositories made with the
// real git command: the cases cli/tests/checklist_test.cpp's pipeline directory does not decide
// (mutation audit 2026-11-30, docs/checklist.md).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "owval/ci/checklist.hpp"
#include "owval/testing/git_history.hpp"
#include "owval/testing/scratch_directory.hpp"

namespace owval::ci {
namespace {
namespace fs = std::filesystem;

// A fresh directory holding prediction.json, reference.h5 and candidate.h5 (the order reads
// names, not contents), committed in the order `commits` gives (owval::testing::CommitInOrder).
fs::path CommittedInOrder(const std::string& name,
                          const std::vector<std::vector<std::string>>& commits) {
  const fs::path d = owval::testing::TestScratch(name);
  for (const char* file : {"prediction.json", "reference.h5", "candidate.h5"})
    std::ofstream(d / file) << file << "\n";
  owval::testing::CommitInOrder(d, commits);
  return d;
}

// "No later than the first trajectory": one commit adding the prediction with the runs is not a
// prediction after them (a pull request made of a single commit).
TEST(GitOrder, APredictionCommittedWithTheTrajectoriesComesFirst) {
  const fs::path d =
      CommittedInOrder("one_commit", {{"prediction.json", "reference.h5", "candidate.h5"}});
  std::string detail;
  EXPECT_TRUE(PredictionCommittedFirst(d, "base..HEAD", &detail)) << detail;
  EXPECT_NE(detail.find(": prediction first"), std::string::npos) << detail;
}

// The trajectories committed and prediction.json never (left on disk, untracked): nothing shows
// it was written before the runs.
TEST(GitOrder, APredictionNeverCommittedFails) {
  const fs::path d = CommittedInOrder("never", {{"reference.h5", "candidate.h5"}});
  std::string detail;
  EXPECT_FALSE(PredictionCommittedFirst(d, "base..HEAD", &detail)) << detail;
  EXPECT_NE(detail.find("prediction.json was not committed before the first trajectory"),
            std::string::npos)
      << detail;
  // Committed at BASE, before the range, it predates the runs added in the range.
  const fs::path before =
      CommittedInOrder("before", {{"prediction.json"}, {"reference.h5", "candidate.h5"}});
  EXPECT_TRUE(PredictionCommittedFirst(before, "HEAD~1..HEAD", &detail)) << detail;
  EXPECT_NE(detail.find("prediction.json predates HEAD~1..HEAD"), std::string::npos) << detail;
}

}  // namespace
}  // namespace owval::ci
