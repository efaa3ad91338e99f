// owval gradcheck: exit codes and the fd_tests.json the PR checklist's item 7 reads.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cli_support.hpp"

namespace owval::testing {
namespace {

TEST(GradCheckCli, WritesChecklistItemSevenInput) {
  const auto file = Scratch() / "fd_tests.json";
  std::filesystem::remove(file);
  const Result r = Owval("gradcheck bond_projection density_projection -o " + file.string());
  EXPECT_EQ(r.exit_code, 0) << r.err << r.out;
  const nlohmann::json j = nlohmann::json::parse(Slurp(file));
  ASSERT_TRUE(j["tests"].is_array());
  EXPECT_EQ(j["tests"].size(), 12u);  // 2 kernels x 2 eps x 3 directions
  for (const auto& t : j["tests"]) {
    EXPECT_TRUE(t["pass"].get<bool>()) << t.dump();
    EXPECT_LE(t["relative_error"].get<double>(), 1e-4);
    EXPECT_TRUE(t.contains("name") && t.contains("kernel") && t.contains("epsilon"));
  }
}

// Issue 14's end-to-end check: 100 split steps of demo1, the fit's loss (elastic and liquid
// centroids against Sibernetic's OpenCL run), reverse pass against central differences.
TEST(GradCheckCli, HundredStepDemo1GradientAgainstTheOpenClRunMatchesFiniteDifferences) {
  const auto demo1 = std::filesystem::path(OWVAL_SHARED_DIR) / "reference/demo1";
  if (ReferenceMissing(demo1 / "position_buffer.txt")) GTEST_SKIP() << "no " << demo1;
  const Result r = Owval("gradcheck reverse --json");
  EXPECT_EQ(r.exit_code, 0) << r.err << r.out;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["tests"].size(), 6u);  // 2 eps x 3 directions
  for (const auto& t : j["tests"]) {
    EXPECT_LE(t["relative_error"].get<double>(), 1e-3) << t.dump();
    EXPECT_NE(t["name"].get<std::string>().find("position_buffer.txt"), std::string::npos);
    EXPECT_NE(t["name"].get<std::string>().find("density_passes=1"), std::string::npos);
  }
}

TEST(GradCheckCli, UnknownKernelIsBadInputAndWritesNothing) {
  const auto file = Scratch() / "fd_tests_bad.json";
  std::filesystem::remove(file);
  const Result r = Owval("gradcheck pressure -o " + file.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("unknown kernel 'pressure'"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(file));
}

}  // namespace
}  // namespace owval::testing
