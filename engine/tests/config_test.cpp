#include "owval/engine/config.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "config_error.hpp"
#include "owval/base/errors.hpp"
#include "owval/testing/scratch_directory.hpp"
#include "owval/testing/test_files.hpp"

namespace owval::engine {
namespace {
namespace fs = std::filesystem;

std::string Minimal(const std::string& connection_rows = "17.1\t14.195\t0\t0\n",
                    const std::string& box = "[simulation box]\n0\n10\n0\n10\n0\n10\n") {
  std::string text = box +
                     "[position]\n5\t5\t5\t2.1\n1\t1\t1\t3\n[velocity]\n0\t0\t0\t0\n0.57735\t0."
                     "57735\t0.57735\t3\n";
  text += "[connection]\n" + connection_rows;
  return text;
}

std::string Connections(const std::string& first) {
  std::string rows = first;
  for (int i = 1; i < 32; ++i) rows += "-1\t0\t0\t0\n";
  return rows;
}

TEST(Config, ReadsSiberneticsOwnOneSprigAndDemo1) {
  if (!fs::exists(testing::kSharedDir / "reference")) GTEST_SKIP() << "no ../shared/reference";
  const SiberneticConfig one =
      ReadSiberneticConfig(testing::kSharedDir / "reference/one_sprig/configuration");
  EXPECT_EQ(one.elastic_count(), 1u);
  EXPECT_EQ(one.liquid_count(), 0u);
  EXPECT_EQ(one.boundary_count(), 2168u);
  EXPECT_EQ(one.connection.size(), 32u);
  EXPECT_FLOAT_EQ(one.connection[0][0], 1180.1f);
  EXPECT_FLOAT_EQ(one.connection[0][1], 14.195f);
  EXPECT_FLOAT_EQ(one.box.ymax, 33.4f);
  const SiberneticConfig demo =
      ReadSiberneticConfig(testing::kSharedDir / "reference/demo1/configuration");
  EXPECT_EQ(demo.elastic_count(), 218u);
  EXPECT_EQ(demo.liquid_count(), 125u);
  EXPECT_EQ(demo.boundary_count(), 17498u);
  EXPECT_FALSE(demo.membranes.empty());
  EXPECT_EQ(demo.particle_mem_index.size(), 218u * 7);
}

TEST(Config, ShortRowsRepeatTheirLastField) {
  const std::string text =
      "[simulation box]\n0\n10\n0\n10\n0\n10\n[position]\n1\t1\t1\t3\n[velocity]\n0\t0\t1\n[end]\n";
  const SiberneticConfig c = ParseSiberneticConfig(text, "cfg");
  EXPECT_FLOAT_EQ(c.velocity[0][3], 1.0f);  // a 3-column normal row gets w = n_z
}

TEST(Config, PhysicalParametersFollowSiberneticsParsingRule) {
  const std::string text =
      "[physical parameters]\nmass: 5.4e-14\ntimeStep: 2e-5\ngravity_y: -9.8\nrho0: 1000 // c\n" +
      Minimal(Connections("1.1\t2\t0\t0\n")) + "[end]\n";
  const SiberneticConfig c = ParseSiberneticConfig(text, "cfg");
  EXPECT_EQ(c.physical_parameters.count("mass"), 1u);
  EXPECT_EQ(c.physical_parameters.count("timeStep"), 0u);   // exponent without a decimal point
  EXPECT_EQ(c.physical_parameters.count("gravity_y"), 0u);  // signed
  EXPECT_EQ(c.physical_parameters.at("rho0"), 1000);
  PhysicsConstants k;
  EXPECT_EQ(ApplyPhysicalParameters(c, &k).size(), 2u);
  EXPECT_DOUBLE_EQ(k.mass_kg, 5.4e-14);
  EXPECT_NE(k.DifferencesFromDefaults().find("mass_kg"), std::string::npos);
}

TEST(Config, RefusesMissingBox) {
  EXPECT_NE(ConfigErrorOf(Minimal(Connections("1.1\t2\t0\t0\n"), "") + "[end]\n")
                .find("missing [simulation box]"),
            std::string::npos);
}

TEST(Config, RefusesNonNumericFieldWithLine) {
  std::string text = Minimal(Connections("1.1\t2\t0\t0\n")) + "[end]\n";
  const std::size_t row = text.find("5\t5\t5");
  ASSERT_NE(row, std::string::npos);
  text[row] = 'x';
  const std::string e = ConfigErrorOf(text);
  EXPECT_NE(e.find("cfg:9:"), std::string::npos) << e;
  EXPECT_NE(e.find("found 'x'"), std::string::npos) << e;
}

TEST(Config, RefusesWrongConnectionCount) {
  EXPECT_NE(
      ConfigErrorOf(Minimal("1.1\t2\t0\t0\n") + "[end]\n").find("expected 32 per elastic particle"),
      std::string::npos);
}

TEST(Config, RefusesConnectionToMissingParticle) {
  EXPECT_NE(
      ConfigErrorOf(Minimal(Connections("17.1\t2\t0\t0\n")) + "[end]\n").find("does not exist"),
      std::string::npos);
}

TEST(Config, RefusesTruncatedFile) {
  EXPECT_NE(ConfigErrorOf(Minimal(Connections("1.1\t2\t0\t0\n"))).find("expected an [end] line"),
            std::string::npos);
}

TEST(Config, RefusesElasticAfterOthers) {
  std::string text =
      "[simulation "
      "box]\n0\n10\n0\n10\n0\n10\n[position]\n1\t1\t1\t3\n5\t5\t5\t2.1\n[velocity]"
      "\n0\t0\t0\t0\n0\t0\t0\t0\n";
  text += "[connection]\n" + Connections("0.1\t2\t0\t0\n") + "[end]\n";
  EXPECT_NE(ConfigErrorOf(text).find("elastic particles must come first"), std::string::npos);
}

TEST(Config, RefusesPositionVelocityMismatch) {
  std::string text =
      "[simulation box]\n0\n10\n0\n10\n0\n10\n[position]\n1\t1\t1\t3\n[velocity]\n[end]\n";
  EXPECT_NE(ConfigErrorOf(text).find("wrong particle count"), std::string::npos);
}

TEST(Config, WriteThenReadRoundTrips) {
  const SiberneticConfig c =
      ParseSiberneticConfig(Minimal(Connections("1.1\t2.5\t0\t0\n")) + "[end]\n", "cfg");
  const fs::path path = owval::testing::TestScratch() / "written.cfg";
  WriteSiberneticConfig(c, path);
  const SiberneticConfig back = ReadSiberneticConfig(path);
  EXPECT_EQ(back.position, c.position);
  EXPECT_EQ(back.velocity, c.velocity);
  EXPECT_EQ(back.connection, c.connection);
}

}  // namespace
}  // namespace owval::engine
