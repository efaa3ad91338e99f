#include "owval/base/atomic_output.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

namespace owval {
namespace {
namespace fs = std::filesystem;

fs::path Fresh(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("owval_atomic_" + std::to_string(::getpid())) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::size_t Entries(const fs::path& dir) {
  return std::size_t(std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}

TEST(AtomicDirectory, AnUncommittedDirectoryLeavesNothing) {
  const fs::path parent = Fresh("uncommitted");
  {
    AtomicDirectory report(parent / "report");
    std::ofstream(report.temporary_path() / "a.txt") << "new";
  }
  EXPECT_EQ(Entries(parent), 0u);
}

TEST(AtomicDirectory, CommitReplacesAnOlderDirectoryWhole) {
  const fs::path parent = Fresh("commit");
  fs::create_directories(parent / "report");
  std::ofstream(parent / "report" / "old.txt") << "old";
  AtomicDirectory report(parent / "report");
  std::ofstream(report.temporary_path() / "new.txt") << "new";
  EXPECT_TRUE(fs::exists(parent / "report" / "old.txt"));  // untouched until the commit
  report.Commit();
  EXPECT_FALSE(fs::exists(parent / "report" / "old.txt"));
  EXPECT_TRUE(fs::exists(parent / "report" / "new.txt"));
  EXPECT_EQ(Entries(parent), 1u);  // no temporary or old copy beside it
}

TEST(AtomicOutput, RemovesTemporariesOfProcessesThatNoLongerRun) {
  const fs::path parent = Fresh("stale");
  // PID 999999999 exceeds any pid_max: no such process.
  std::ofstream(parent / ".out.txt.tmp.999999999.0") << "left by a killed run";
  fs::create_directories(parent / ".out.txt.tmp.999999999.1");
  std::ofstream(parent / (".out.txt.tmp." + std::to_string(::getppid()) + ".0")) << "alive";
  WriteFileAtomically(parent / "out.txt", "x");
  EXPECT_FALSE(fs::exists(parent / ".out.txt.tmp.999999999.0"));
  EXPECT_FALSE(fs::exists(parent / ".out.txt.tmp.999999999.1"));
  EXPECT_TRUE(fs::exists(parent / (".out.txt.tmp." + std::to_string(::getppid()) + ".0")));
}

}  // namespace
}  // namespace owval
