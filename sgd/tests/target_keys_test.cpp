// --target keys that do nothing are refused, naming the key: `period=1:ref=x` fitted the period
// to 1 and ignored ref=x silently (only rms reads a reference).
#include <gtest/gtest.h>

#include "owval/base/errors.hpp"
#include "owval/sgd/targets.hpp"

namespace owval::sgd {
namespace {

std::string Refusal(const std::string& text) {
  try {
    ParseTarget(text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "accepted";
}

TEST(TargetKeys, ReferenceOnANonRmsTargetIsRefused) {
  EXPECT_EQ(Refusal("period=1:ref=x"),
            "--target period=1:ref=x: ref applies only to rms targets, not period");
  EXPECT_EQ(Refusal("half_amplitude=1.7:scale=1:ref=r.h5"),
            "--target half_amplitude=1.7:scale=1:ref=r.h5: ref applies only to rms targets, not "
            "half_amplitude");
  EXPECT_EQ(Refusal("equilibrium=18:ref=r.h5:weight=2"),
            "--target equilibrium=18:ref=r.h5:weight=2: ref applies only to rms targets, not "
            "equilibrium");
  EXPECT_EQ(Refusal("rms=0:scale=1:ref=r.h5"), "accepted");
}

TEST(TargetKeys, UnknownMetricIsRefusedBeforeAnySimulation) {
  EXPECT_EQ(Refusal("perod=1"),
            "--target perod=1: unknown metric 'perod' (period, half_amplitude, equilibrium, rms)");
  EXPECT_EQ(Refusal("period=1:scale=2:weight=0.5"), "accepted");
}

TEST(TargetKeys, UnknownOptionIsRefusedNamingIt) {
  EXPECT_EQ(Refusal("period=1:tolerance=0.1"),
            "--target period=1:tolerance=0.1: unknown option 'tolerance' (scale, weight, ref)");
}

}  // namespace
}  // namespace owval::sgd
