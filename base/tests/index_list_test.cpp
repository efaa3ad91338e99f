#include "owval/base/index_list.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "owval/base/errors.hpp"

namespace owval {
namespace {

std::string IndexListError(const std::string& text) {
  try {
    ParseIndexList(text, "--at");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(IndexList, ReadsCommaSeparatedIndicesInTheirOrder) {
  EXPECT_EQ(ParseIndexList("0,15,100,200", "--at"), (std::vector<std::size_t>{0, 15, 100, 200}));
  EXPECT_EQ(ParseIndexList("7", "--at"), (std::vector<std::size_t>{7}));
  EXPECT_EQ(ParseIndexList("3,1", "--at"), (std::vector<std::size_t>{3, 1}));
}

TEST(IndexList, RefusesEmptyListsAndItemsNamingTheFlag) {
  EXPECT_EQ(IndexListError(""), "--at: expected comma-separated frame indices, found ''");
  EXPECT_EQ(IndexListError("0,"), "--at: expected comma-separated frame indices, found '0,'");
  EXPECT_EQ(IndexListError("0,,1"), "--at: expected comma-separated frame indices, found ''");
}

TEST(IndexList, RefusesSignsNonDigitsAndIndicesPast64Bits) {
  EXPECT_EQ(IndexListError("-1"), "--at: expected comma-separated frame indices, found '-1'");
  EXPECT_EQ(IndexListError("0,1.5"), "--at: expected comma-separated frame indices, found '1.5'");
  EXPECT_EQ(IndexListError("99999999999999999999"),
            "--at: expected comma-separated frame indices, found '99999999999999999999'");
}

TEST(IndexList, RefusesAFrameListedTwice) {
  EXPECT_EQ(IndexListError("0,15,0"), "--at: frame 0 is listed twice");
}

}  // namespace
}  // namespace owval
