#include "owval/base/atomic_output.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <vector>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "owval/base/errors.hpp"
#include "owval/testing/scratch_directory.hpp"
#include "owval/testing/test_files.hpp"

namespace owval {
namespace {
namespace fs = std::filesystem;
using testing::FileBytes;

fs::path Fresh(const std::string& name) { return owval::testing::TestScratch(name); }

using testing::CountEntries;

TEST(AtomicDirectory, AnUncommittedDirectoryLeavesNothing) {
  const fs::path parent = Fresh("uncommitted");
  {
    AtomicDirectory report(parent / "report");
    std::ofstream(report.temporary_path() / "a.txt") << "new";
  }
  EXPECT_EQ(CountEntries(parent), 0u);
}

TEST(AtomicDirectory, CommitReplacesAnOlderDirectoryWhole) {
  const fs::path parent = Fresh("commit");
  {  // an older report owval wrote
    AtomicDirectory older(parent / "report");
    std::ofstream(older.temporary_path() / "old.txt") << "old";
    older.Commit();
  }
  AtomicDirectory report(parent / "report");
  std::ofstream(report.temporary_path() / "new.txt") << "new";
  EXPECT_TRUE(fs::exists(parent / "report" / "old.txt"));  // untouched until the commit
  report.Commit();
  EXPECT_FALSE(fs::exists(parent / "report" / "old.txt"));
  EXPECT_TRUE(fs::exists(parent / "report" / "new.txt"));
  EXPECT_EQ(CountEntries(parent), 1u);  // no temporary or old copy beside it
}

TEST(AtomicDirectory, RefusesToReplaceADirectoryOwvalDidNotWrite) {
  const fs::path parent = Fresh("foreign");
  fs::create_directories(parent / "report" / "sub");
  std::ofstream(parent / "report" / "sub" / "thesis.tex") << "precious";
  EXPECT_THROW(AtomicDirectory(parent / "report"), InputError);
  AtomicDirectory zarr(parent / "store", [](const fs::path&) { return false; });
  fs::create_directories(parent / "store");
  std::ofstream(parent / "store" / "notes.txt") << "put there while the work ran";
  EXPECT_THROW(zarr.Commit(), InputError);
  EXPECT_TRUE(fs::exists(parent / "report" / "sub" / "thesis.tex"));
  EXPECT_TRUE(fs::exists(parent / "store" / "notes.txt"));
  AtomicDirectory empty(parent / "empty");
  fs::create_directories(parent / "empty");  // an empty directory holds nothing to lose
  EXPECT_NO_THROW(empty.Commit());
}

TEST(OutputGroup, ADirectoryInTheWayOfAFileIsRefusedAndKept) {
  const fs::path parent = Fresh("group_directory");
  fs::create_directories(parent / "worm.wcon");
  std::ofstream(parent / "worm.wcon" / "notes.txt") << "precious";
  OutputGroup group;
  WriteFileAtomically(group.Stage(parent / "a.txt"), "a");
  WriteFileAtomically(group.Stage(parent / "worm.wcon"), "{}");
  EXPECT_THROW(group.Commit(), InputError);
  EXPECT_EQ(FileBytes(parent / "worm.wcon" / "notes.txt"), "precious");
  EXPECT_FALSE(fs::exists(parent / "a.txt"));  // nothing moved: the set stays whole
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

TEST(OutputGroup, CommitReplacesEveryMemberAndLeavesNoMarker) {
  const fs::path dir = Fresh("group_commit");
  std::ofstream(dir / "a.txt") << "old a";
  std::ofstream(dir / "b.txt") << "old b";
  OutputGroup group;
  AtomicOutput a(dir / "a.txt");
  a.stream() << "new a";
  group.Adopt(&a);
  std::ofstream(group.Stage(dir / "b.txt")) << "new b";
  EXPECT_EQ(FileBytes(dir / "a.txt"), "old a");  // nothing visible before the commit
  group.Commit();
  EXPECT_EQ(FileBytes(dir / "a.txt"), "new a");
  EXPECT_EQ(FileBytes(dir / "b.txt"), "new b");
  EXPECT_EQ(CountEntries(dir), 2u);  // no marker, no temporary
}

TEST(OutputGroup, AnUncommittedGroupRemovesItsTemporaries) {
  const fs::path dir = Fresh("group_uncommitted");
  {
    OutputGroup group;
    AtomicOutput a(dir / "a.txt");
    a.stream() << "a";
    group.Adopt(&a);
    std::ofstream(group.Stage(dir / "b.txt")) << "b";
  }
  EXPECT_EQ(CountEntries(dir), 0u);
}

// A rerun that writes fewer files than the run before it: the earlier run's extra file goes with
// the commit, not before it, and a directory goes only when the caller says it is its own.
TEST(OutputGroup, CommitRemovesRetiredOutputsAndOnlyThen) {
  const fs::path dir = Fresh("group_retire");
  std::ofstream(dir / "a.txt") << "old a";
  std::ofstream(dir / "stale.txt") << "earlier run";
  fs::create_directory(dir / "users_store");
  fs::create_directory(dir / "owval_store");
  OutputGroup group;
  std::ofstream(group.Stage(dir / "a.txt")) << "new a";
  group.Retire(dir / "stale.txt");
  group.Retire(dir / "users_store");
  group.Retire(dir / "owval_store", true);
  group.Retire(dir / "never_written.txt");
  EXPECT_EQ(FileBytes(dir / "stale.txt"), "earlier run");  // nothing changes before the commit
  EXPECT_TRUE(fs::exists(dir / "owval_store"));
  group.Commit();
  EXPECT_EQ(FileBytes(dir / "a.txt"), "new a");
  EXPECT_FALSE(fs::exists(dir / "stale.txt"));
  EXPECT_FALSE(fs::exists(dir / "owval_store"));
  EXPECT_TRUE(fs::is_directory(dir / "users_store"));
  EXPECT_EQ(CountEntries(dir), 2u);  // a.txt and users_store: no marker, no temporary
}

TEST(OutputGroup, AnUncommittedGroupKeepsWhatItWouldRetire) {
  const fs::path dir = Fresh("group_retire_uncommitted");
  std::ofstream(dir / "stale.txt") << "earlier run";
  {
    OutputGroup group;
    std::ofstream(group.Stage(dir / "a.txt")) << "new a";
    group.Retire(dir / "stale.txt");
  }
  EXPECT_EQ(FileBytes(dir / "stale.txt"), "earlier run");
  EXPECT_EQ(CountEntries(dir), 1u);
}

// A commit that stops between its renames (here: a member whose temporary is missing) leaves
// the marker, and readers refuse the files it names instead of pairing new with old.
TEST(OutputGroup, AnInterruptedCommitMakesReadersRefuseItsFiles) {
  const fs::path dir = Fresh("group_interrupted");
  std::ofstream(dir / "b.txt") << "old b";
  std::ofstream(dir / "other.txt") << "not in the group";
  OutputGroup group;
  AtomicOutput a(dir / "a.txt");
  a.stream() << "new a";
  group.Adopt(&a);
  group.Stage(dir / "b.txt");  // never written
  EXPECT_THROW(group.Commit(), InputError);
  EXPECT_EQ(FileBytes(dir / "a.txt"), "new a");
  EXPECT_TRUE(fs::exists(CommitMarkerPath(dir)));
  try {
    ReadWholeFile(dir / "a.txt");
    ADD_FAILURE() << "read a file of an interrupted commit";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("a.txt: incomplete"), std::string::npos) << e.what();
  }
  EXPECT_EQ(ReadWholeFile(dir / "other.txt"), "not in the group");
}

std::string CheckError(const fs::path& destination) {
  return testing::InputErrorOf([&] { CheckOutputPath(destination); });
}

// `owval pipeline free_fall` (default -o reports/free_fall) was refused in a directory without
// reports/, as "reports is not a directory": a relative path's missing first component was
// taken for the nearest existing ancestor instead of the working directory.
TEST(OutputPath, MissingDirectoriesOfARelativePathCanBeCreated) {
  const fs::path dir = Fresh("relative");
  const fs::path before = fs::current_path();
  fs::current_path(dir);
  EXPECT_EQ(CheckError("reports/free_fall/index.html"), "no error");
  EXPECT_EQ(CheckError("index.html"), "no error");
  std::ofstream("plain") << "x";
  EXPECT_EQ(CheckError("plain/sub/index.html"),
            "plain/sub: cannot be created: plain is not a directory");
  fs::create_directory("taken");
  EXPECT_EQ(CheckError("taken"), "taken: is a directory; expected a file to write");
  fs::current_path(before);
  EXPECT_EQ(CheckError(dir / "new" / "deeper" / "index.html"), "no error");
  EXPECT_EQ(CheckError(""), "output path is empty");
}

// As root, `bench engine --json-out /dev/full` ran, then renamed its JSON over /dev/full: the
// device node became a regular file. A FIFO stands for any such node (mkfifo needs no root):
// refused before work, by every writer, and at commit when one appeared meanwhile; kept as it is.
TEST(OutputPath, ADeviceFifoOrSocketIsNeverReplaced) {
  const fs::path dir = Fresh("special");
  const fs::path fifo = dir / "fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const std::string refused =
      fifo.string() + ": is a device, FIFO or socket, not a regular file; expected a file to write";
  EXPECT_EQ(CheckError(fifo), refused);
  try {
    WriteFileAtomically(fifo, "x");
    ADD_FAILURE() << "wrote over a FIFO";
  } catch (const InputError& e) {
    EXPECT_EQ(e.what(), refused);
  }
  const fs::path later = dir / "later";
  {
    AtomicOutput out(later);
    out.stream() << "x";
    ASSERT_EQ(::mkfifo(later.c_str(), 0600), 0);
    EXPECT_THROW(out.Commit(), InputError);
  }
  try {
    WriteFilesTogether({{dir / "a.txt", "a"}, {fifo, "b"}});
    ADD_FAILURE() << "a group wrote over a FIFO";
  } catch (const InputError& e) {
    EXPECT_EQ(e.what(), refused);
  }
  EXPECT_TRUE(fs::is_fifo(fifo));
  EXPECT_TRUE(fs::is_fifo(later));
  EXPECT_FALSE(fs::exists(dir / "a.txt"));
  std::vector<std::string> left;
  for (const auto& entry : fs::directory_iterator(dir)) left.push_back(entry.path().filename());
  std::sort(left.begin(), left.end());
  EXPECT_EQ(left, (std::vector<std::string>{"fifo", "later"}));  // no temporary either
}

// As root, access() allowed /proc, so `bench engine --json-out /proc/x.json` ran the whole
// benchmark before failing to write. A folder that refuses a new file is refused up front, and
// the check leaves nothing behind in a folder that accepts one.
TEST(OutputPath, AFolderThatRefusesNewFilesIsRefusedEvenToRoot) {
  if (!fs::is_directory("/proc/self")) GTEST_SKIP() << "no /proc";
  const std::string error = CheckError("/proc/owval_x.json");
  EXPECT_EQ(error.rfind("/proc/owval_x.json: cannot be written: /proc", 0), 0u) << error;
  const fs::path dir = Fresh("probe");
  EXPECT_EQ(CheckError(dir / "x.json"), "no error");
  EXPECT_TRUE(fs::is_empty(dir));
}

// `owval run CONFIG -o /proc/x`, `frames ... -o /proc/x`, `predict -o /proc/x/p.json` printed
// libstdc++'s "filesystem error: cannot create directories: No such file or directory [/proc/x]"
// or named position_buffer.txt, and `convert IN /sys/x.zarr` named a path inside the store: every
// check and every writer names the outermost directory it must create, and what stops it.
TEST(OutputPath, AMissingDirectoryIsNamedWithWhatStopsIt) {
  if (!fs::is_directory("/proc/self")) GTEST_SKIP() << "no /proc";
  const std::string expected = "/proc/owval_x: cannot be created: /proc ";
  std::string error = CheckError("/proc/owval_x/y/position_buffer.txt");
  EXPECT_EQ(error.rfind(expected, 0), 0u) << error;
  EXPECT_EQ(error.find("No such file"), std::string::npos) << error;  // /proc exists
  try {
    AtomicOutput out("/proc/owval_x/p.json");
    ADD_FAILURE() << "an output under /proc";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(expected, 0), 0u) << e.what();
  }
  for (const char* zarr : {"/proc/owval_x", "/proc/owval_x/a.zarr"}) {
    try {
      CheckOutputDirectory(zarr);
      ADD_FAILURE() << zarr;
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(expected, 0), 0u) << e.what();
    }
  }
  const fs::path dir = Fresh("directory");
  std::ofstream(dir / "plain") << "x";
  try {
    CheckOutputDirectory(dir / "plain");
    ADD_FAILURE() << "a file taken for a directory";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              (dir / "plain").string() + ": exists and is not a directory; expected a directory");
  }
  EXPECT_NO_THROW(CheckOutputDirectory(dir / "new.zarr"));
  EXPECT_NO_THROW(CreateOutputDirectories(dir / "a" / "b"));
  EXPECT_TRUE(fs::is_directory(dir / "a" / "b"));
  try {
    CreateOutputDirectories(dir / "plain" / "sub");
    ADD_FAILURE() << "a directory under a file";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), (dir / "plain" / "sub").string() + ": cannot be created: " +
                                         (dir / "plain").string() + " is not a directory");
  }
}

// The CLI's last resort for a filesystem_error no check foresaw: the path first, one line.
TEST(OutputPath, AFilesystemErrorIsDescribedPathFirst) {
  const fs::filesystem_error e("cannot create directories", "/proc/x",
                               std::make_error_code(std::errc::no_such_file_or_directory));
  EXPECT_EQ(DescribeFilesystemError(e),
            "/proc/x: cannot create directories: No such file or directory");
}

// Ctrl-C during `render` or `convert OUT.zarr` left ".v.mp4.tmp.PID.N" (or a temporary store)
// behind: the signal's default action skips destructors. In a child that signals itself with
// outputs of each kind unfinished, every temporary is gone and the child dies of SIGINT; a
// committed output and a kept (resumable) temporary stay; folders the command made are removed
// when left empty.
TEST(AtomicOutput, SigintRemovesTheTemporariesOfUnfinishedOutputs) {
  const fs::path dir = Fresh("sigint");
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    RemoveTemporariesOnSignal();
    MissingDirectories made(dir / "frames" / "deeper");  // left empty: removed too
    fs::create_directories(dir / "frames" / "deeper");
    WriteFileAtomically(dir / "done.txt", "whole");
    AtomicOutput kept(dir / "resumable.txt");
    kept.stream() << "partial";
    kept.KeepOnFailure();
    AtomicOutput video(dir / "v.mp4");
    video.stream() << "frames";
    AtomicDirectory store(dir / "z.zarr", [](const fs::path&) { return false; });
    fs::create_directories(store.temporary_path() / "body" / "positions");
    std::ofstream(store.temporary_path() / "body" / "positions" / "0.0.0") << "chunk";
    OutputGroup frames;
    std::ofstream(frames.Stage(dir / "frame_0.png")) << "png";
    const pid_t grandchild = ::fork();  // a forked helper (RunContained's) that is terminated
    if (grandchild == 0) std::raise(SIGTERM);
    int ignored = 0;
    ::waitpid(grandchild, &ignored, 0);
    if (!fs::exists(video.temporary_path())) std::_Exit(3);  // it removed its parent's files
    std::raise(SIGINT);
    std::_Exit(0);  // not reached
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGINT) << status;
  std::vector<std::string> left;
  for (const auto& e : fs::directory_iterator(dir)) left.push_back(e.path().filename().string());
  std::sort(left.begin(), left.end());
  ASSERT_EQ(left.size(), 2u);
  EXPECT_EQ(left[0].rfind(".resumable.txt.tmp.", 0), 0u) << left[0];  // '.' sorts first
  EXPECT_EQ(left[1], "done.txt");
}

// fit and frames left an empty output folder behind when they failed with exit 2.
TEST(MissingDirectories, RemovesTheFoldersItFoundMissingWhenLeftEmpty) {
  const fs::path dir = Fresh("missing");
  {
    MissingDirectories guard(dir / "a" / "b");
    fs::create_directories(dir / "a" / "b");
  }
  EXPECT_TRUE(fs::is_empty(dir));
  {
    MissingDirectories guard(dir / "a" / "b");
    fs::create_directories(dir / "a" / "b");
    std::ofstream(dir / "a" / "kept.txt") << "x";  // not empty: kept, with its file
  }
  EXPECT_TRUE(fs::exists(dir / "a" / "kept.txt"));
  EXPECT_FALSE(fs::exists(dir / "a" / "b"));
  {
    MissingDirectories guard(dir / "c");
    fs::create_directories(dir / "c");
    guard.Keep();
  }
  EXPECT_TRUE(fs::is_directory(dir / "c"));
  {
    MissingDirectories guard(dir);  // existing: never removed
  }
  EXPECT_TRUE(fs::is_directory(dir));
}

}  // namespace
}  // namespace owval
