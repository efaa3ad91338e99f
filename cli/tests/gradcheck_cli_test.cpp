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
