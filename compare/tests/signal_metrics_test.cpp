#include "owval/compare/signal_metrics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "owval/base/errors.hpp"
#include "owval/trajectory/formats.hpp"

namespace owval::compare {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct Signal {
  std::vector<double> t, v;
};

// equilibrium + drift·t + A·e^(−γt)·sin(2πt/T), sampled every dt.
Signal Oscillation(double period, double amplitude, double equilibrium, double gamma, double drift,
                   double dt, double duration) {
  Signal s;
  for (double t = 0; t <= duration; t += dt) {
    s.t.push_back(t);
    s.v.push_back(equilibrium + drift * t +
                  amplitude * std::exp(-gamma * t) * std::sin(2 * kPi * t / period + 0.3));
  }
  return s;
}

TEST(SignalMetrics, MeasuresPeriodAmplitudeAndEquilibriumOfAPureSine) {
  const Signal s = Oscillation(0.7e-3, 1.5, 18.0, 0, 0, 1e-6, 20e-3);
  const SignalMetrics m = MeasureSignal(s.t, s.v);
  ASSERT_TRUE(m.period_s);
  EXPECT_NEAR(*m.period_s, 0.7e-3, 0.7e-3 * 1e-5);
  EXPECT_LT(*m.period_spread_s, 1e-8);
  EXPECT_NEAR(*m.half_amplitude, 1.5, 1e-4);
  EXPECT_NEAR(m.equilibrium, 18.0, 1e-3);
  EXPECT_NEAR(*m.drift_per_s, 0, 1e-2);
  EXPECT_NEAR(*m.log_decrement, 0, 1e-4);
  EXPECT_EQ(m.upward_crossings, 28u);
  EXPECT_TRUE(m.whole_cycles);
}

TEST(SignalMetrics, LogDecrementMatchesExponentialDamping) {
  const double period = 1e-3, gamma = 200;  // decrement per cycle = γ·T = 0.2
  const Signal s = Oscillation(period, 2.0, 5.0, gamma, 0, 1e-6, 10e-3);
  const SignalMetrics m = MeasureSignal(s.t, s.v);
  ASSERT_TRUE(m.log_decrement);
  EXPECT_NEAR(*m.log_decrement, gamma * period, 0.01);
  EXPECT_NEAR(*m.period_s, period, period * 2e-3);
}

TEST(SignalMetrics, DriftIsTheSlopeOfCycleMeans) {
  const Signal s = Oscillation(1e-3, 1.0, 3.0, 0, 25.0, 1e-6, 20e-3);
  const SignalMetrics m = MeasureSignal(s.t, s.v);
  ASSERT_TRUE(m.drift_per_s);
  EXPECT_NEAR(*m.drift_per_s, 25.0, 0.25);
}

TEST(SignalMetrics, SettlingTimeOfAStepResponse) {
  Signal s;  // 10 → 0 exponential decay toward 4: |v − 4| ≤ 2%·4 = 0.08 when 6e^(−t/τ) ≤ 0.08
  const double tau = 1e-3;
  for (double t = 0; t <= 20e-3; t += 1e-6) {
    s.t.push_back(t);
    s.v.push_back(4 + 6 * std::exp(-t / tau));
  }
  const SignalMetrics m = MeasureSignal(s.t, s.v);
  ASSERT_TRUE(m.settling_time_s);
  const double expected = tau * std::log(6 / (0.02 * m.final_value));
  EXPECT_NEAR(*m.settling_time_s, expected, 2e-6);
}

TEST(SignalMetrics, WindowRestrictsTheSamples) {
  const Signal s = Oscillation(1e-3, 1.0, 0.0, 0, 0, 1e-6, 10e-3);
  const SignalMetrics m = MeasureSignal(s.t, s.v, {2e-3, 6e-3});
  EXPECT_NEAR(m.window_start_s, 2e-3, 1.5e-6);  // first sample at or after 2 ms
  EXPECT_NEAR(m.window_end_s, 6e-3, 1e-6);
  EXPECT_EQ(m.upward_crossings, 4u);
}

TEST(SignalMetrics, RefusesMismatchedOrTooShortSignals) {
  EXPECT_THROW(MeasureSignal({0, 1}, {1}), InputError);
  EXPECT_THROW(MeasureSignal({0, 1, 2}, {1, 2, 3}, {5, 6}), InputError);
}

TEST(SignalMetrics, NoCrossingsLeavesPeriodEmpty) {
  const SignalMetrics m = MeasureSignal({0, 1, 2, 3}, {1, 2, 3, 4});
  EXPECT_FALSE(m.period_s);
  EXPECT_NEAR(*m.half_amplitude, 1.5, 1e-12);
}

// Golden check on Sibernetic's own one_sprig run (bundled copy of ../shared/reference).
TEST(SignalMetricsGolden, OneSprigElasticParticleY) {
  const std::filesystem::path path = std::filesystem::path(OWVAL_SOURCE_DIR) /
                                     "reference_trajectories/one_sprig/position_buffer.txt";
  const Trajectory t = ReadTrajectory(path);
  const SignalMetrics m = MeasureSignal(t.time_s, ParticleSeries(t, 0, 1));
  ASSERT_TRUE(m.period_s);
  EXPECT_NEAR(*m.period_s, 0.7246e-3, 0.7246e-3 * 1e-3);
  EXPECT_NEAR(*m.half_amplitude, 1.694, 1.694 * 2e-3);
  EXPECT_NEAR(m.equilibrium, 18.352, 0.005);
}

TEST(SignalMetricsGolden, Demo1ElasticCubeFallsAndSettles) {
  const std::filesystem::path path =
      std::filesystem::path(OWVAL_SHARED_DIR) / "reference/demo1/position_buffer.txt";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "no " << path;
  const Trajectory t = ReadTrajectory(path);
  const SignalMetrics m = MeasureSignal(t.time_s, CentroidSeries(t, GroupIndices(t, "elastic"), 1));
  EXPECT_NEAR(m.initial_value, 44.42, 0.01);
  EXPECT_LT(m.final_value, 8.0);  // rests near the floor
  ASSERT_TRUE(m.settling_time_s);
  EXPECT_LT(*m.settling_time_s, 0.1);
  EXPECT_NEAR(m.time_of_minimum_s, 8e-3, 2e-3);  // free fall from 44 cu takes ≈ 7.8 ms
}

}  // namespace
}  // namespace owval::compare
