#include "owval/base/contained.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <csignal>
#include <stdexcept>

#include "owval/base/errors.hpp"

namespace owval {
namespace {

std::string ErrorOf(const std::function<void()>& work, int timeout_s = 120) {
  try {
    ContainedOptions options;
    options.timeout_s = timeout_s;
    RunContained("f.h5", "HDF5: libhdf5", work, options);
  } catch (const InputError& e) {
    return std::string("InputError: ") + e.what();
  } catch (const std::exception& e) {
    return std::string("other: ") + e.what();
  }
  return "ok";
}

TEST(RunContained, ReturnsWhenTheWorkSucceeds) {
  EXPECT_EQ(ErrorOf([] {}), "ok");
}

TEST(RunContained, PassesTheChildsRefusalThrough) {
  EXPECT_EQ(ErrorOf([] { throw InputError("f.h5", 0, "HDF5: attribute box has 2 values"); }),
            "InputError: f.h5: HDF5: attribute box has 2 values");
  EXPECT_EQ(ErrorOf([] { throw std::logic_error("bug"); }), "other: bug");
}

// A library's crash in the child is a refusal naming the file, not owval's crash.
TEST(RunContained, TurnsACrashIntoARefusalNamingTheFile) {
  const std::string error = ErrorOf([] { std::raise(SIGSEGV); });
  EXPECT_EQ(error.rfind("InputError: f.h5: HDF5: libhdf5 crashed", 0), 0u) << error;
  EXPECT_NE(error.find("corrupt or hostile file"), std::string::npos);
}

TEST(RunContained, KillsAChildPastItsTimeout) {
  EXPECT_EQ(ErrorOf(
                [] {
                  for (;;) pause();
                },
                1),
            "InputError: f.h5: HDF5: libhdf5 ran past 1 s: corrupt or hostile file");
}

}  // namespace
}  // namespace owval
