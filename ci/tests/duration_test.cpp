// ParseDuration (`owval ci validate --stability 10s`): decimal numbers with s or ms only.
#include <gtest/gtest.h>

#include "owval/base/errors.hpp"
#include "owval/ci/stability_run.hpp"

namespace owval::ci {
namespace {

TEST(ParseDuration, TakesSecondsAndMilliseconds) {
  EXPECT_EQ(ParseDuration("10s", "--stability"), 10.0);
  EXPECT_EQ(ParseDuration("10", "--stability"), 10.0);
  EXPECT_EQ(ParseDuration("10 s", "--stability"), 10.0);
  EXPECT_DOUBLE_EQ(ParseDuration("500ms", "--stability"), 0.5);
  EXPECT_EQ(ParseDuration("2.5e-1s", "--stability"), 0.25);
}

// std::stod read "0x10s" as a 16 s run, and " 10s" with its leading space.
TEST(ParseDuration, RefusesWhatIsNotADecimalDuration) {
  for (const char* text : {"0x10s", "infs", "nan", " 10s", "10m", "10 ms s", "s", "ms", "", "0s",
                           "-1s", "1e400s", "10ss", "1e"})
    EXPECT_THROW(ParseDuration(text, "--stability"), InputError) << "'" << text << "'";
}

}  // namespace
}  // namespace owval::ci
