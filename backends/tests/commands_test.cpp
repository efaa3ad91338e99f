// backends/commands.hpp: what `owval compare` and `owval bench backends` refuse before any run.
#include "owval/backends/commands.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "owval/base/errors.hpp"
#include "owval/testing/scratch_directory.hpp"

namespace owval::backends {
namespace {
namespace fs = std::filesystem;

std::string ErrorOf(const CompareRequest& r) {
  try {
    CompareNamed(r);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(BackendCommands, SetsAreNameValuePairs) {
  EXPECT_EQ(ParseSets({"a=1", "b=x=y", "c="}),
            (std::map<std::string, std::string>{{"a", "1"}, {"b", "x=y"}, {"c", ""}}));
  EXPECT_THROW(ParseSets({"=1"}), InputError);
  EXPECT_THROW(ParseSets({"novalue"}), InputError);
}

TEST(BackendCommands, AFileIsNeverComparedWithABackendName) {
  const fs::path dir = owval::testing::TestScratch("commands");
  fs::create_directories(dir / "sub");
  std::ofstream(dir / "ref.txt") << "x\n";
  CompareRequest r;
  r.reference = (dir / "ref.txt").string();
  r.candidate = (dir / "missing.h5").string();
  EXPECT_NE(ErrorOf(r).find("no such trajectory file (and " + r.reference + " is a file"),
            std::string::npos)
      << ErrorOf(r);
  r.candidate = (dir / "sub").string();
  EXPECT_NE(ErrorOf(r).find("is a directory; expected a trajectory file like"), std::string::npos);
  std::swap(r.reference, r.candidate);
  EXPECT_NE(ErrorOf(r).find("is a directory; expected a trajectory file like"), std::string::npos);
  fs::remove_all(dir);
}

TEST(BackendCommands, ANameWithASlashThatIsNoFileIsNamed) {
  CompareRequest r;
  r.reference = "no/such.h5";
  r.candidate = "opencl";  // a backend name, not a file in the working directory
  EXPECT_EQ(ErrorOf(r), "no/such.h5: no such trajectory file (and not a backend name)");
}

}  // namespace
}  // namespace owval::backends
