// owval scenario list|show|generate end to end, and the --param parser it shares with predict.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "owval/base/errors.hpp"
#include "owval/engine/config.hpp"
#include "owval/scenarios/scenario.hpp"
#include "owval/testing/scratch_directory.hpp"

namespace owval::scenarios {
namespace {
namespace fs = std::filesystem;

TEST(ParseOverrides, TakesNameEqualsNumberOnly) {
  const auto o = ParseOverrides({"rest_length_cu=12.5", "beads=3"});
  EXPECT_EQ(o.at("rest_length_cu"), 12.5);
  EXPECT_EQ(o.at("beads"), 3);
  EXPECT_THROW(ParseOverrides({"rest_length_cu"}), InputError);
  EXPECT_THROW(ParseOverrides({"rest_length_cu=12cu"}), InputError);
  EXPECT_THROW(ParseOverrides({"rest_length_cu="}), InputError);
}

// The last of two values won silently.
TEST(ParseOverrides, RefusesANameGivenTwice) {
  try {
    ParseOverrides({"beads=3", "rest_length_cu=1", "beads=4"});
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "--param beads=4: beads is given twice");
  }
}

struct CliRun {
  int exit_code;
  std::string out;
};

CliRun Owval(const std::string& args) {
  const fs::path out = owval::testing::TestScratch() / "output.txt";
  const std::string command = (fs::path(OWVAL_BINARY_DIR) / "owval").string() + " -q " + args +
                              " > " + out.string() + " 2>&1";
  const int status = std::system(command.c_str());
  std::ifstream in(out);
  std::stringstream text;
  text << in.rdbuf();
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, text.str()};
}

class ScenarioCli : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(fs::path(OWVAL_BINARY_DIR) / "owval")) GTEST_SKIP() << "owval not built";
  }
};

TEST_F(ScenarioCli, ListNamesEveryManifest) {
  const CliRun r = Owval("scenario list");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  for (const std::string& name : ListScenarios(OWVAL_SOURCE_DIR))
    EXPECT_NE(r.out.find(name + "\t"), std::string::npos) << name;
}

TEST_F(ScenarioCli, ShowPrintsTheManifest) {
  const CliRun r = Owval("scenario show hanging_chain");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_EQ(nlohmann::json::parse(r.out)["predictor"], "hanging_chain");
  EXPECT_EQ(Owval("scenario show no_such_scenario").exit_code, 2);
}

TEST_F(ScenarioCli, GenerateAppliesParametersAndRefusesUnknownOnes) {
  const fs::path file = owval::testing::TestScratch() / "generated.config";
  fs::remove(file);
  const CliRun r = Owval("scenario generate one_sprig -o " + file.string() +
                         " --param rest_length_cu=12 --param start_y_cu=19");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const engine::SiberneticConfig c = engine::ReadSiberneticConfig(file);
  EXPECT_FLOAT_EQ(c.connection[0][1], 12.0f);
  EXPECT_FLOAT_EQ(c.position[0][1], 19.0f);
  fs::remove(file);
  const CliRun bad = Owval("scenario generate one_sprig -o " + file.string() + " --param bogus=1");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.out.find("bogus"), std::string::npos) << bad.out;
  EXPECT_FALSE(fs::exists(file));
}

}  // namespace
}  // namespace owval::scenarios
