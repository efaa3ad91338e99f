// Every test program's main: GoogleTest's own, plus the listener that gives each test its
// scratch directory (owval/testing/scratch_directory.hpp) and removes it when the test ends.
#include <gtest/gtest.h>

#include "owval/testing/scratch_directory.hpp"

namespace {

class ScratchDirectories : public ::testing::EmptyTestEventListener {
  void OnTestStart(const ::testing::TestInfo& test) override {
    owval::testing::detail::RunningTestName() =
        std::string(test.test_suite_name()) + "." + test.name();
  }
  // After TearDown and every destructor of the test: nothing of the test still uses its files.
  void OnTestEnd(const ::testing::TestInfo&) override {
    owval::testing::detail::TestScratchSlot().reset();
    owval::testing::detail::RunningTestName().clear();
  }
  void OnTestProgramEnd(const ::testing::UnitTest&) override {
    owval::testing::detail::ProgramScratchSlot().reset();
  }
};

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  // GoogleTest calls end events in reverse order: a kept directory's path precedes the verdict.
  ::testing::UnitTest::GetInstance()->listeners().Append(new ScratchDirectories);
  return RUN_ALL_TESTS();
}
