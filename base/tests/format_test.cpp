#include "owval/base/format.hpp"

#include <gtest/gtest.h>

namespace owval {
namespace {

TEST(FormatNumber, KeepsTheRequestedSignificantDigits) {
  EXPECT_EQ(FormatNumber(0.000724637, 4), "0.0007246");
  EXPECT_EQ(FormatNumber(1.694, 7), "1.694");
  EXPECT_EQ(FormatNumber(5e-5, 17), "5.0000000000000002e-05");
}

TEST(FormatPercent, ScalesAFractionToPercent) {
  EXPECT_EQ(FormatPercent(0.0213), "2.13%");
  EXPECT_EQ(FormatPercent(-0.488, 3), "-48.8%");
}

}  // namespace
}  // namespace owval
