#pragma once
// Runs read once per test program, for tests that compare against them or modify a copy (only
// programs that link owval_trajectory include this): the bundled one_sprig run, and Sibernetic's
// demo1 run from ../shared when it is there.
#include <cstdlib>
#include <filesystem>

#include "owval/testing/test_files.hpp"
#include "owval/trajectory/formats.hpp"

namespace owval::testing {

inline const Trajectory& BundledOneSprigRun() {
  static const Trajectory run = ReadTrajectory(kBundledOneSprig);
  return run;
}

// Sibernetic's demo1 run (../shared/reference/demo1), or null when ../shared is absent.
inline const Trajectory* SiberneticDemo1Run() {
  static const std::filesystem::path path =
      std::filesystem::path(OWVAL_SHARED_DIR) / "reference/demo1/position_buffer.txt";
  if (!std::filesystem::exists(path)) return nullptr;
  static const Trajectory run = ReadTrajectory(path);
  return &run;
}

}  // namespace owval::testing

// In a test: skip without ../shared's demo1 run, or fail when OWVAL_REQUIRE_REFERENCE is set.
#define OWVAL_REQUIRE_DEMO1()                                                                 \
  if (!owval::testing::SiberneticDemo1Run()) {                                                \
    if (std::getenv("OWVAL_REQUIRE_REFERENCE")) FAIL() << "no ../shared/reference/demo1 run"; \
    GTEST_SKIP() << "no ../shared/reference/demo1";                                           \
  }
