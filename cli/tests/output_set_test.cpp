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

}  // namespace
}  // namespace owval::testing
