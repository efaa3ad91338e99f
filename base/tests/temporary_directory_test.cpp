// owval's own scratch directories (TemporaryDirectory: `owval bench`, `owval checklist
// --scenario`) are removed however the work ends, Ctrl-C included.
#include "owval/base/temporary_directory.hpp"

#include <gtest/gtest.h>
#include <signal.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "owval/base/atomic_output.hpp"
#include "owval/testing/scratch_directory.hpp"

namespace owval {
namespace {
namespace fs = std::filesystem;

std::size_t Entries(const fs::path& dir) {
  std::size_t n = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++n;
  return n;
}

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
    EXPECT_EQ(Entries(tmp), 2u);
    throw std::runtime_error("the work failed");
  } catch (const std::runtime_error&) {
  }
  EXPECT_EQ(Entries(tmp), 0u);
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
  EXPECT_EQ(Entries(tmp), 0u);
}

}  // namespace
}  // namespace owval
