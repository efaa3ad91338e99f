// backends/commands.hpp: what `owval compare` and `owval bench backends` refuse before any run.
#include "owval/backends/commands.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <utility>
#include <vector>

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

// Each form of compare takes its own flags; a flag of the other form is refused, not ignored
// (`compare A.txt B.txt --scenarios demo1` compared the files and said nothing of demo1).
TEST(BackendCommands, TwoFilesRefuseTheSuitesFlags) {
  const fs::path dir = owval::testing::TestScratch("commands_files");
  std::ofstream(dir / "ref.txt") << "x\n";  // never read: the refusal comes first
  const std::vector<std::pair<std::string, std::function<void(CompareRequest&)>>> flags = {
      {"--scenarios", [](CompareRequest& r) { r.scenarios.names = {"demo1"}; }},
      {"--sibernetic", [](CompareRequest& r) { r.scenarios.sibernetic = "/opt/sibernetic"; }},
      {"--reference-dir", [](CompareRequest& r) { r.scenarios.reference_dir = "/tmp"; }},
      {"--set", [](CompareRequest& r) { r.sets = {"k=1"}; }},
      {"--backends", [](CompareRequest& r) { r.backends.file = "b.json"; }},
      {"--cache", [](CompareRequest& r) { r.backends.cache.directory = "/tmp"; }},
      {"--no-cache", [](CompareRequest& r) { r.backends.cache.enabled = false; }}};
  for (const auto& [flag, give] : flags) {
    CompareRequest r;
    r.reference = r.candidate = (dir / "ref.txt").string();
    give(r);
    EXPECT_EQ(ErrorOf(r), "compare: " + flag +
                              " applies to two backend names; the reference and candidate given "
                              "are trajectory files");
  }
}

TEST(BackendCommands, TwoBackendNamesRefuseTheFilesFlags) {
  const std::vector<std::pair<std::string, std::function<void(CompareRequest&)>>> flags = {
      {"--manifest", [](CompareRequest& r) { r.manifest = "m.json"; }},
      {"the tracked quantity (--particle, --group, --axis)",
       [](CompareRequest& r) { r.track.axis = "x"; }},
      {"the tracked quantity (--particle, --group, --axis)",
       [](CompareRequest& r) { r.track.particle = 3; }},
      {"--frames", [](CompareRequest& r) { r.frames = "0,15"; }},
      {"--scale", [](CompareRequest& r) { r.scale = 1.0; }},
      {compare::kGateThresholdFields[0].flag, [](CompareRequest& r) {
         r.thresholds.resize(compare::kGateThresholdFields.size());
         r.thresholds[0] = 0.01;  // tighter than the default: ignored, it would not be applied
       }}};
  for (const auto& [flag, give] : flags) {
    CompareRequest r;
    r.reference = "opencl";
    r.candidate = "owval";
    give(r);
    EXPECT_EQ(ErrorOf(r), "compare opencl owval: " + flag +
                              " applies to two trajectory files; with backend names each "
                              "scenario's manifest sets the track and gates");
  }
}

}  // namespace
}  // namespace owval::backends
