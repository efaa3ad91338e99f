// Issue 18: the files of one `owval run` appear together or not at all. They are finished under
// temporary names and moved into place as one OutputGroup; a run stopped between those moves
// leaves the group's marker (.owval-commit), and every owval reader refuses the files it names.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "cli_support.hpp"

namespace owval::testing {
namespace {
namespace fs = std::filesystem;

void ExpectRefusedAsIncomplete(const fs::path& file) {
  const Result r = Owval("inspect " + file.string());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << "one line: " << r.err;
  EXPECT_NE(r.err.find(file.filename().string() + ": incomplete"), std::string::npos) << r.err;
}

TEST(RunOutputs, AnInterruptedMoveIntoPlaceIsRefusedAndARerunMendsIt) {
  const fs::path out = Scratch() / "output_set";
  fs::remove_all(out);
  const std::string run = "run one_sprig --time 0.001 --log-step 5 --out " + out.string();
  ASSERT_EQ(Owval(run).exit_code, 0);
  ASSERT_FALSE(fs::exists(out / ".owval-commit"));
  // What a run killed between its renames leaves beside its files.
  std::ofstream(out / ".owval-commit") << "position_buffer.txt\ntrajectory.h5\n";
  ExpectRefusedAsIncomplete(out / "position_buffer.txt");
  ExpectRefusedAsIncomplete(out / "trajectory.h5");
  ASSERT_EQ(Owval(run).exit_code, 0);
  EXPECT_FALSE(fs::exists(out / ".owval-commit"));
  EXPECT_EQ(Owval("inspect " + (out / "trajectory.h5").string()).exit_code, 0);
  for (const auto& e : fs::directory_iterator(out))
    EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos) << e.path();
}

void ExpectRefusedBeforeWork(const Result& r, const std::string& says) {
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << "one line: " << r.err;
  EXPECT_NE(r.err.find(says), std::string::npos) << r.err;
}

// Directories the user put where a run writes are refused before the run, and never deleted.
TEST(RunOutputs, DirectoriesInTheWayOfOutputsAreRefusedAndKept) {
  const fs::path worm = fs::path(OWVAL_SHARED_DIR) / "reference/worm_alone_0.6s/configuration";
  if (ReferenceMissing(worm)) GTEST_SKIP() << "no ../shared/reference";
  for (const char* name : {"worm.wcon", "worm_motion_log.txt"}) {
    const fs::path out = Scratch() / "in_the_way";
    fs::remove_all(out);
    fs::create_directories(out / name);
    std::ofstream(out / name / "notes.txt") << "precious";
    ExpectRefusedBeforeWork(
        Owval("run " + worm.string() + " --time 0.001 --log-step 10 -o " + out.string()),
        std::string(name) + ": is a directory; expected a file to write");
    EXPECT_EQ(Slurp(out / name / "notes.txt"), "precious");
    EXPECT_FALSE(fs::exists(out / "trajectory.h5"));
  }
}

TEST(RunOutputs, AUsersFilesInTheCheckpointDirectoryStay) {
  const fs::path out = Scratch() / "checkpoint_notes";
  fs::remove_all(out);
  fs::create_directories(out / "checkpoint");
  std::ofstream(out / "checkpoint" / "notes.txt") << "x";
  for (const char* every : {"", " --checkpoint-every 5"}) {
    ASSERT_EQ(Owval("run one_sprig --time 0.001 -o " + out.string() + every).exit_code, 0);
    EXPECT_EQ(Slurp(out / "checkpoint" / "notes.txt"), "x");
    EXPECT_FALSE(fs::exists(out / "checkpoint" / "checkpoint.bin"));  // complete: removed
  }
}

TEST(RunOutputs, AFreshRunDoesNotDeleteAnInterruptedRunsCheckpoint) {
  const fs::path out = Scratch() / "interrupted_checkpoint";
  fs::remove_all(out);
  fs::create_directories(out / "checkpoint");
  std::ofstream(out / "checkpoint" / "checkpoint.bin") << "an interrupted run's state";
  ExpectRefusedBeforeWork(Owval("run one_sprig --time 0.001 -o " + out.string()),
                          "continue it with owval run --resume " + out.string());
  EXPECT_EQ(Slurp(out / "checkpoint" / "checkpoint.bin"), "an interrupted run's state");
  EXPECT_FALSE(fs::exists(out / "trajectory.h5"));
}

TEST(RunOutputs, AnInterruptedWcsphRunExits143WithItsPartialTrajectory) {
  const fs::path out = Scratch() / "wcsph_interrupted";
  fs::remove_all(out);
  // A frame every step and 3 s before the signal: the sanitizer build on a loaded 2-core machine
  // reached step 19 in 2 s, one frame at --log-step 20, and inspect rightly refuses one frame.
  std::string line = "timeout --preserve-status -s TERM 3 ";
  line += OWVAL_EXE;
  line +=
      " --quiet run hydrostatic_tank --backend wcsph --time 0.2 --log-step 1 -o " + out.string();
  const Result r = RunCaptured(line);
  EXPECT_EQ(r.exit_code, 143) << r.err;
  EXPECT_NE(r.err.find("partial trajectory in " + out.string()), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(out / "position_buffer.partial.txt"));
  EXPECT_EQ(Owval("inspect " + (out / "trajectory.partial.h5").string()).exit_code, 0);
  EXPECT_FALSE(fs::exists(out / "checkpoint"));
}

TEST(ConvertOutputs, OnlyAnOwvalZarrStoreIsReplaced) {
  const fs::path dir = Scratch() / "zarr_replace";
  fs::remove_all(dir);
  ASSERT_EQ(Owval("run one_sprig --time 0.001 -o " + (dir / "r1").string()).exit_code, 0);
  const std::string h5 = (dir / "r1" / "trajectory.h5").string();
  fs::create_directories(dir / "myproj.zarr" / "sub");
  std::ofstream(dir / "myproj.zarr" / "sub" / "thesis.tex") << "x";
  ExpectRefusedBeforeWork(Owval("convert " + h5 + " " + (dir / "myproj.zarr").string()),
                          "not an OME-Zarr store owval wrote");
  EXPECT_EQ(Slurp(dir / "myproj.zarr" / "sub" / "thesis.tex"), "x");
  // owval's own store is replaced; one with a file of the user's added is not.
  const std::string store = (dir / "owval.zarr").string();
  ASSERT_EQ(Owval("convert " + h5 + " " + store).exit_code, 0);
  ASSERT_EQ(Owval("convert " + h5 + " " + store).exit_code, 0);
  std::ofstream(dir / "owval.zarr" / "body" / "notes.txt") << "mine";
  ExpectRefusedBeforeWork(Owval("convert " + h5 + " " + store), "not an OME-Zarr store");
  EXPECT_EQ(Slurp(dir / "owval.zarr" / "body" / "notes.txt"), "mine");
}

}  // namespace
}  // namespace owval::testing
