// --set NAME=VALUE of `owval compare A B` and `owval bench backends` ({set:NAME} in commands).
#include <gtest/gtest.h>

#include "owval/backends/commands.hpp"
#include "owval/base/errors.hpp"

namespace owval::backends {
namespace {

TEST(ParseSets, RefusesANameGivenTwice) {
  try {
    ParseSets({"a=1", "b=2", "a=3"});
    FAIL() << "the last a won silently";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "--set a=3: a is given twice");
  }
}

}  // namespace
}  // namespace owval::backends
