#pragma once
// The bundled one_sprig run read once per test program, for tests that compare against it or
// modify a copy (only programs that link owval_trajectory include this).
#include "owval/testing/test_files.hpp"
#include "owval/trajectory/formats.hpp"

namespace owval::testing {

inline const Trajectory& BundledOneSprigRun() {
  static const Trajectory run = ReadTrajectory(kBundledOneSprig);
  return run;
}

}  // namespace owval::testing
