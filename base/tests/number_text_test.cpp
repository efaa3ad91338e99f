// ParseDecimal and ParseAssignments: the one parser of numbers typed on the command line.
#include <gtest/gtest.h>

#include "owval/base/errors.hpp"
#include "owval/base/number_text.hpp"

namespace owval {
namespace {

TEST(ParseDecimal, TakesDecimalNumbers) {
  EXPECT_EQ(ParseDecimal("16"), 16.0);
  EXPECT_EQ(ParseDecimal("-2.5"), -2.5);
  EXPECT_EQ(ParseDecimal("+.5"), 0.5);
  EXPECT_EQ(ParseDecimal("5."), 5.0);
  EXPECT_EQ(ParseDecimal("1.62e8"), 1.62e8);
  EXPECT_EQ(ParseDecimal("7E-3"), 7e-3);
  EXPECT_EQ(ParseDecimal("1e+2"), 100.0);
  EXPECT_EQ(ParseDecimal("1e-400"), 0.0);  // below double's range: still a number
}

// strtod reads every one of these (0x10 as 16, inf, nan, " 1" as 1) or stops early ("1e").
TEST(ParseDecimal, RefusesWhatStrtodAlsoReads) {
  for (const char* text :
       {"0x10",  "0X1p4", "inf", "-inf",  "infinity", "nan", "NAN(1)", " 1", "1 ",
        "\t1",   "1e",    "1e+", "e5",    ".",        "-",   "+",      "",   "1..2",
        "1.2.3", "5cu",   "1,5", "1e999", "-1e400",   "--1", "1_000"})
    EXPECT_FALSE(ParseDecimal(text).has_value()) << "'" << text << "'";
}

TEST(ParseAssignments, KeepsOrderAndRefusesARepeatedName) {
  const auto a = ParseAssignments({"b=2", "a=1e3"}, "--set");
  ASSERT_EQ(a.size(), 2u);
  EXPECT_EQ(a[0].first, "b");
  EXPECT_EQ(a[1].second, 1e3);
  try {
    ParseAssignments({"A=1", "B=3", "A=2"}, "--set");
    FAIL() << "a repeated name was accepted";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "--set A=2: A is given twice");
  }
}

TEST(ParseAssignments, RefusesAnythingButNameEqualsDecimal) {
  for (const char* text : {"A", "=1", "A=", "A=0x10", "A=inf", "A=nan", "A= 1", "A=1e"})
    EXPECT_THROW(ParseAssignments({text}, "--param"), InputError) << text;
  try {
    ParseAssignments({"beads=0x10"}, "--param");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("--param beads=0x10: expected NAME=NUMBER", 0), 0u)
        << e.what();
  }
}

}  // namespace
}  // namespace owval
