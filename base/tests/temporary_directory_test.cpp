// owval's own scratch directories (TemporaryDirectory: `owval bench`, `owval checklist
// --scenario`) are removed however the work ends, Ctrl-C included; the tests' (ScratchDirectory,
// owval/testing/scratch_directory.hpp) are the same, kept only when asked: tests that kept their
// files or removed them only when they passed left 12,511 owval_* entries, about 40 GB, in /tmp.
#include "owval/base/temporary_directory.hpp"

#include <gtest/gtest.h>
#include <signal.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "owval/base/atomic_output.hpp"
#include "owval/testing/scratch_directory.hpp"

namespace owval {
namespace {
namespace fs = std::filesystem;

using testing::CountEntries;

// TMPDIR set to DIR while it exists (temp_directory_path() reads it).
class TmpdirSetTo {
 public:
  explicit TmpdirSetTo(const fs::path& dir) {
    if (const char* was = std::getenv("TMPDIR")) previous_ = was;
    ::setenv("TMPDIR", dir.c_str(), 1);
  }
  ~TmpdirSetTo() {
    if (previous_.empty())
      ::unsetenv("TMPDIR");
    else
      ::setenv("TMPDIR", previous_.c_str(), 1);
  }

 private:
  std::string previous_;
};

TEST(TemporaryDirectory, IsUnderTmpdirOwnedAndRemovedWithItsContentsEvenOnAnError) {
  const fs::path tmp = testing::TestScratch("tmp");
  const TmpdirSetTo set(tmp);
  try {
    const TemporaryDirectory a("owval-test"), b("owval-test");
    EXPECT_EQ(a.path().parent_path(), tmp);
    EXPECT_NE(a.path(), b.path());
    fs::create_directories(a.path() / "out" / "deeper");
    std::ofstream(a.path() / "out" / "deeper" / "file.txt") << "x";
    EXPECT_EQ(CountEntries(tmp), 2u);
    throw std::runtime_error("the work failed");
  } catch (const std::runtime_error&) {
  }
  EXPECT_EQ(CountEntries(tmp), 0u);
}

// Ctrl-C during `owval checklist --scenario` or `owval bench` skipped the destructor.
TEST(TemporaryDirectory, SigintRemovesIt) {
  const fs::path tmp = testing::TestScratch("tmp");
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    ::setenv("TMPDIR", tmp.c_str(), 1);
    RemoveTemporariesOnSignal();
    const TemporaryDirectory scratch("owval-reference");
    fs::create_directories(scratch.path() / "out");
    std::ofstream(scratch.path() / "out" / "reference.h5") << "partial";
    std::raise(SIGINT);
    std::_Exit(0);  // not reached
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGINT) << status;
  EXPECT_EQ(CountEntries(tmp), 0u);
}

// Run by the next test only (ctest does not run a disabled test): a test that fails early.
TEST(ScratchDirectory, DISABLED_FailsEarlyAfterWritingAFile) {
  fs::create_directories(testing::TestScratch() / "sub");
  std::ofstream(testing::TestScratch() / "sub" / "evidence.txt") << "x";
  ASSERT_TRUE(false) << "failing on purpose";
}

// A test that fails, even by an ASSERT's early return, leaves nothing in TMPDIR; with
// OWVAL_KEEP_TEST_FILES=1 its directory is kept and named.
TEST(ScratchDirectory, AFailedTestLeavesNothingUnlessAskedToKeepIt) {
  const fs::path tmp = testing::TestScratch("tmp"), log = testing::TestScratch() / "log.txt";
  const std::string run = "TMPDIR=" + tmp.string() + " " +
                          fs::read_symlink("/proc/self/exe").string() +
                          " --gtest_also_run_disabled_tests" +
                          " --gtest_filter=ScratchDirectory.DISABLED_FailsEarlyAfterWritingAFile";
  int status =
      std::system(("OWVAL_KEEP_TEST_FILES= " + run + " > " + log.string() + " 2>&1").c_str());
  EXPECT_EQ(WEXITSTATUS(status), 1);
  EXPECT_EQ(CountEntries(tmp), 0u);
  status = std::system(("OWVAL_KEEP_TEST_FILES=1 " + run + " > " + log.string() + " 2>&1").c_str());
  EXPECT_EQ(WEXITSTATUS(status), 1);
  ASSERT_EQ(CountEntries(tmp), 1u);
  const fs::path kept = fs::directory_iterator(tmp)->path();
  EXPECT_TRUE(fs::exists(kept / "sub" / "evidence.txt"));
  std::stringstream output;
  output << std::ifstream(log).rdbuf();
  EXPECT_NE(output.str().find("kept " + kept.string()), std::string::npos) << output.str();
}

// A test's scratch directory is a TemporaryDirectory: SIGINT removes it too, unless it is kept;
// a forked child's signal never removes its parent's.
TEST(ScratchDirectory, SigintRemovesItUnlessKeptAndNeverTheParents) {
  const fs::path tmp = testing::TestScratch("tmp");
  for (const bool keep : {false, true}) {
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      ::setenv("TMPDIR", tmp.c_str(), 1);
      ::setenv("OWVAL_KEEP_TEST_FILES", keep ? "1" : "", 1);
      RemoveTemporariesOnSignal();
      const testing::ScratchDirectory scratch("signal");
      std::ofstream(scratch / "evidence.txt") << "x";
      std::raise(SIGINT);
      std::_Exit(0);  // not reached
    }
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGINT) << status;
    EXPECT_EQ(CountEntries(tmp), keep ? 1u : 0u) << "keep " << keep;
  }
}

}  // namespace
}  // namespace owval
