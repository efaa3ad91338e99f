// The tests' scratch directories (owval/testing/scratch_directory.hpp) leave nothing behind,
// however a test ends: tests that kept their files or removed them only when they passed left
// 12,511 owval_* entries, about 40 GB, in /tmp.
#include "owval/testing/scratch_directory.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace owval {
namespace {
namespace fs = std::filesystem;

std::size_t Entries(const fs::path& dir) {
  std::size_t n = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++n;
  return n;
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
  EXPECT_EQ(Entries(tmp), 0u);
  status = std::system(("OWVAL_KEEP_TEST_FILES=1 " + run + " > " + log.string() + " 2>&1").c_str());
  EXPECT_EQ(WEXITSTATUS(status), 1);
  ASSERT_EQ(Entries(tmp), 1u);
  const fs::path kept = fs::directory_iterator(tmp)->path();
  EXPECT_TRUE(fs::exists(kept / "sub" / "evidence.txt"));
  std::stringstream output;
  output << std::ifstream(log).rdbuf();
  EXPECT_NE(output.str().find("kept " + kept.string()), std::string::npos) << output.str();
}

}  // namespace
}  // namespace owval
