#include "owval/base/failure.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace owval {
namespace {

template <class Error>
Failure Of(const Error& error) {
  return DescribeFailure(std::make_exception_ptr(error));
}

TEST(Failure, EachErrorKindHasItsLineAndExitCode) {
  const Failure input = Of(InputError("a.txt", 3, "expected x"));
  EXPECT_EQ(input.line, "error: a.txt:3: expected x");
  EXPECT_EQ(input.exit_code, kExitBadInput);
  const Failure environment = Of(EnvironmentError("no OSMesa context"));
  EXPECT_EQ(environment.line, "environment: no OSMesa context");
  EXPECT_EQ(environment.exit_code, kExitEnvironment);
  const Failure simulation = Of(SimulationError("NaN at step 4"));
  EXPECT_EQ(simulation.line, "error: NaN at step 4");
  EXPECT_EQ(simulation.exit_code, kExitGateFailed);
  const Failure other = Of(std::runtime_error("cancelled"));
  EXPECT_EQ(other.line, "error: cancelled");
  EXPECT_EQ(other.exit_code, kExitBadInput);
}

TEST(Failure, AFilesystemErrorNamesItsPathFirst) {
  const Failure f = Of(std::filesystem::filesystem_error(
      "cannot create directories", "/proc/x",
      std::make_error_code(std::errc::no_such_file_or_directory)));
  EXPECT_EQ(f.line.rfind("error: /proc/x", 0), 0u) << f.line;
  EXPECT_EQ(f.exit_code, kExitBadInput);
}

TEST(Failure, AnythingElseIsRethrown) {
  EXPECT_THROW(DescribeFailure(std::make_exception_ptr(42)), int);
}

}  // namespace
}  // namespace owval
