#pragma once
// Phase-3 measurements of one scalar signal over time (design notes §4). Definitions are fixed:
//  - zero-crossing period: centre on the window mean, upward sign changes, linear interpolation
//    of crossing times, period = mean spacing (count and spread reported);
//  - half-amplitude: half the peak-to-peak over whole cycles; equilibrium: mean over whole cycles;
//  - damping: logarithmic decrement of successive peaks (about the equilibrium);
//  - settling time: first time after which the signal stays within a ±2% band of its final value
//    (2% of |final value|; of the range when the final value is 0); reported only when the signal
//    stays in the band for at least the last 10% of the window;
//  - drift: slope of a linear fit of the per-cycle means (units per second).
#include <optional>
#include <string>
#include <vector>

namespace owval::compare {

struct SignalWindow {
  double start_s = -1;  // < 0: from the first sample
  double end_s = -1;    // < 0: to the last sample
};

struct SignalMetrics {
  std::size_t samples = 0;
  double window_start_s = 0, window_end_s = 0;
  // Zero crossings (upward) of the mean-centred signal.
  std::size_t upward_crossings = 0;
  std::optional<double> period_s;         // mean spacing; empty when fewer than 2 crossings
  std::optional<double> period_spread_s;  // standard deviation of spacings
  std::optional<double> half_amplitude;   // over whole cycles (else over the window)
  double equilibrium = 0;                 // mean over whole cycles (else over the window)
  std::optional<double> drift_per_s;      // slope of cycle means; needs >= 2 whole cycles
  std::optional<double> log_decrement;    // mean ln(peak_k / peak_{k+1}) of |peak - equilibrium|
  std::optional<double> settling_time_s;  // empty if it never settles within the window
  double initial_value = 0, minimum = 0, maximum = 0, final_value = 0;
  double time_of_minimum_s = 0, time_of_maximum_s = 0;  // first occurrence
  bool whole_cycles = false;  // true when the amplitude/equilibrium came from whole cycles
};

// `time_s` and `values` have the same length (at least 2). Throws InputError when not.
SignalMetrics MeasureSignal(const std::vector<double>& time_s, const std::vector<double>& values,
                            const SignalWindow& window = {});

}  // namespace owval::compare
