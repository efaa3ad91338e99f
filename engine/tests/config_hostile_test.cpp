// Hostile configurations (issue 18 items 2 and 7): each is refused with one line naming the file
// and what was wrong, before the engine sizes anything from it.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>

#include <string>

#include "config_error.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/memory_budget.hpp"
#include "owval/engine/config.hpp"
#include "owval/testing/test_files.hpp"

namespace owval::engine {
namespace {

// One elastic particle (with its 32 connection slots, all empty) and one boundary particle.
std::string Config(const std::string& box, const std::string& tail) {
  std::string text = "[simulation box]\n" + box +
                     "[position]\n5\t5\t5\t2.1\n1\t1\t1\t3\n[velocity]\n0\t0\t0\t0\n0\t0\t0\t3\n"
                     "[connection]\n";
  for (int i = 0; i < 32; ++i) text += "-1\t0\t0\t0\n";
  return text + tail;
}
const std::string kBox = "0\n10\n0\n10\n0\n10\n";

std::string MemIndex(const std::string& first) {
  std::string rows = "[particleMemIndex]\n" + first;
  for (int i = 1; i < 7; ++i) rows += "-1\n";
  return rows;
}

TEST(ConfigHostile, AcceptsAValidMembraneIndex) {
  // Vertices 0 0 0 are the one elastic particle (degenerate, but an index check only).
  EXPECT_EQ(ConfigErrorOf(Config(kBox, "[membranes]\n0\t0\t0\n" + MemIndex("0\n") + "[end]\n")),
            "no error");
}

// Was a heap use-after-free read in the membrane pass (membranes.cpp:57).
TEST(ConfigHostile, RefusesAParticleMemIndexNamingNoMembrane) {
  EXPECT_EQ(ConfigErrorOf(Config(kBox, "[membranes]\n0\t0\t0\n" + MemIndex("5\n") + "[end]\n")),
            "cfg: [particleMemIndex] row 0 names membrane 5, which does not exist (1 membranes; "
            "-1 = none)");
  EXPECT_NE(ConfigErrorOf(Config(kBox, "[membranes]\n0\t0\t0\n" + MemIndex("-7\n") + "[end]\n"))
                .find("names membrane -7"),
            std::string::npos);
}

TEST(ConfigHostile, RefusesMembranesWithoutParticleMemIndex) {
  EXPECT_EQ(ConfigErrorOf(Config(kBox, "[membranes]\n0\t0\t0\n[end]\n")),
            "cfg: [membranes] without [particleMemIndex]: expected 7 membrane slots per elastic "
            "particle");
}

TEST(ConfigHostile, RefusesAnIndexNoIntHolds) {
  EXPECT_EQ(ConfigErrorOf(Config(kBox, "[membranes]\n1e30\t0\t0\n[end]\n")),
            "cfg:48: membrane vertex 1000000015047466219876688855040.000000 is not a particle or "
            "membrane index");
}

TEST(ConfigHostile, RefusesAConnectionTo1e30) {
  std::string text = Config(kBox, "[end]\n");
  text.replace(text.find("-1\t0\t0\t0\n"), 9, "1e30\t1\t0\t0\n");
  EXPECT_NE(ConfigErrorOf(text).find(
                "connection row 0 links to particle 1000000015047466219876688855040"),
            std::string::npos);
}

// Type 7.5 ran as a particle of no class (it moved, but as neither liquid, elastic nor
// boundary), and (int) of a type 1e30 is undefined.
TEST(ConfigHostile, RefusesATypeCodeOfNoClass) {
  for (const char* type : {"7.5", "0.5", "1e30", "-2"}) {
    std::string text = Config(kBox, "[end]\n");
    text.replace(text.find("\t3\n[velocity]"), 2, std::string("\t") + type);
    EXPECT_NE(ConfigErrorOf(text).find("[position] row has type "), std::string::npos)
        << type << ": " << ConfigErrorOf(text);
  }
  std::string text = Config(kBox, "[end]\n");
  const std::size_t at = text.find("\t3\n[velocity]");
  const std::string line = std::to_string(std::count(text.begin(), text.begin() + at, '\n') + 1);
  text.replace(at, 2, "\t7.5");
  EXPECT_EQ(ConfigErrorOf(text),
            "cfg:" + line +
                ": [position] row has type 7.5: expected x, y, z and a type 1.x "
                "(liquid), 2.x (elastic) or 3.x (boundary)");
}

// A row of three fields read its third (a coordinate) as the type, as Sibernetic's loader
// repeats a row's last field, and the message had no line.
TEST(ConfigHostile, ARowOfThreeFieldsIsReportedOnItsLine) {
  std::string text = Config(kBox, "[end]\n");
  const std::size_t at = text.find("\t3\n[velocity]");
  const std::size_t row = text.rfind('\n', at) + 1;
  const std::string line = std::to_string(std::count(text.begin(), text.begin() + row, '\n') + 1);
  text.replace(row, at + 2 - row, "17.5\t20.04\t17.5");
  EXPECT_EQ(ConfigErrorOf(text).rfind(
                "cfg:" + line + ": [position] row has type 17.5: expected x, y, z", 0),
            0u)
      << ConfigErrorOf(text);
}

// A spring whose rest length is negative can never relax; an empty slot's (-1 partner) is unread.
TEST(ConfigHostile, RefusesANegativeRestLength) {
  std::string text = Config(kBox, "[end]\n");
  text.replace(text.find("-1\t0\t0\t0\n"), 9, "1\t-5\t0\t0\n");
  EXPECT_EQ(ConfigErrorOf(text), "cfg: connection row 0 has rest length -5 cu: expected 0 or more");
  text = Config(kBox, "[end]\n");
  text.replace(text.find("-1\t0\t0\t0\n"), 9, "-1\t-5\t0\t0\n");
  EXPECT_EQ(ConfigErrorOf(text), "no error");
}

// Was an 11 GB allocation and bad_alloc for three particles.
TEST(ConfigHostile, RefusesABoxWhoseNeighbourGridExceedsTheBudget) {
  const std::string error = ConfigErrorOf(Config("0\n1e6\n0\n1e6\n0\n1e6\n", "[end]\n"));
  EXPECT_NE(error.find("cfg: [simulation box] 1000000.000000 x 1000000.000000 x 1000000.000000 "
                       "cu needs a neighbour grid of "),
            std::string::npos)
      << error;
  SetMemoryBudgetBytes(1 << 20);  // 65,536 cells
  EXPECT_NE(
      ConfigErrorOf(Config("0\n300\n0\n300\n0\n300\n", "[end]\n")).find("over the limit of 65536"),
      std::string::npos);
  EXPECT_EQ(ConfigErrorOf(Config("0\n100\n0\n100\n0\n100\n", "[end]\n")), "no error");
  SetMemoryBudgetBytes(0);
}

// A box no count of cells holds (r0_cu = 1e30 in a generator) was said to need
// "18446744073709551615 cells": the saturated count, printed as a number.
TEST(ConfigHostile, ABoxPastCountingSaysSoInsteadOfASaturatedCellCount) {
  Box box;
  box.xmax = box.ymax = box.zmax = 2e31f;
  EXPECT_EQ(NeighbourGridCells(box, 3.34), std::numeric_limits<std::size_t>::max());
  const std::string error = ConfigErrorOf(Config("0\n2e31\n0\n2e31\n0\n2e31\n", "[end]\n"));
  EXPECT_NE(error.find("needs a neighbour grid of more than 10^19 cells"), std::string::npos)
      << error;
  EXPECT_EQ(error.find("18446744073709551615"), std::string::npos) << error;
}

TEST(ConfigHostile, RefusesAnInvertedBox) {
  EXPECT_EQ(ConfigErrorOf(Config("10\n0\n0\n10\n0\n10\n", "[end]\n")),
            "cfg: [simulation box]: a maximum is below its minimum");
}

TEST(ConfigHostile, RefusesAnOverflowingPhysicalParameterAndAHugeLine) {
  const std::string head = "[physical parameters]\nh: 1.0e999\n";
  EXPECT_EQ(ConfigErrorOf(head + Config(kBox, "[end]\n")),
            "cfg:2: [physical parameters] h is not a finite number");
  const std::string spaces = "[physical parameters]\nh:" + std::string(100000, ' ') + "3.0\n";
  EXPECT_EQ(ConfigErrorOf(spaces + Config(kBox, "[end]\n")),
            "cfg:2: [physical parameters] line longer than 1024 characters");
}

TEST(ConfigHostile, NeighbourGridCellsMatchesTheEngineGrid) {
  Box box;
  box.xmax = 10, box.ymax = 20, box.zmax = 0;  // 10 / 6.68 -> 1 + 2; 20 / 6.68 -> 2 + 2; 0 + 2
  EXPECT_EQ(NeighbourGridCells(box, 3.34), 3u * 4u * 2u);
}

}  // namespace
}  // namespace owval::engine
