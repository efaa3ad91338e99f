#include "owval/compare/signal_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "owval/base/errors.hpp"

namespace owval::compare {
namespace {

struct Window {
  std::vector<double> t, v;
};

Window Select(const std::vector<double>& time_s, const std::vector<double>& values,
              const SignalWindow& window) {
  if (time_s.size() != values.size())
    throw InputError("signal: " + std::to_string(time_s.size()) + " times but " +
                     std::to_string(values.size()) + " values");
  Window w;
  for (std::size_t i = 0; i < time_s.size(); ++i) {
    if (window.start_s >= 0 && time_s[i] < window.start_s) continue;
    if (window.end_s >= 0 && time_s[i] > window.end_s) continue;
    w.t.push_back(time_s[i]);
    w.v.push_back(values[i]);
  }
  if (w.t.size() < 2)
    throw InputError("signal: the time window holds " + std::to_string(w.t.size()) +
                     " samples, expected at least 2");
  return w;
}

double Mean(const std::vector<double>& v, std::size_t begin, std::size_t end) {
  return std::accumulate(v.begin() + begin, v.begin() + end, 0.0) /
         static_cast<double>(end - begin);
}

// Upward crossings of the centred signal: times (linearly interpolated) and the index of the
// first sample at or after each crossing.
void UpwardCrossings(const Window& w, double centre, std::vector<double>* times,
                     std::vector<std::size_t>* after) {
  for (std::size_t i = 1; i < w.v.size(); ++i) {
    const double a = w.v[i - 1] - centre, b = w.v[i] - centre;
    if (a < 0 && b >= 0) {
      times->push_back(w.t[i - 1] + (w.t[i] - w.t[i - 1]) * (-a) / (b - a));
      after->push_back(i);
    }
  }
}

double Slope(const std::vector<double>& x, const std::vector<double>& y) {
  const double mx = Mean(x, 0, x.size()), my = Mean(y, 0, y.size());
  double sxy = 0, sxx = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sxy += (x[i] - mx) * (y[i] - my);
    sxx += (x[i] - mx) * (x[i] - mx);
  }
  return sxx > 0 ? sxy / sxx : 0;
}

void MeasureCycles(const Window& w, const std::vector<double>& crossing_t,
                   const std::vector<std::size_t>& after, SignalMetrics* m) {
  const std::size_t begin = after.front(), end = after.back();  // whole cycles: [begin, end)
  const auto [lo, hi] = std::minmax_element(w.v.begin() + begin, w.v.begin() + end);
  m->half_amplitude = (*hi - *lo) / 2;
  m->equilibrium = Mean(w.v, begin, end);
  m->whole_cycles = true;
  std::vector<double> cycle_mid_t, cycle_mean, peaks;
  for (std::size_t c = 0; c + 1 < after.size(); ++c) {
    cycle_mid_t.push_back((crossing_t[c] + crossing_t[c + 1]) / 2);
    cycle_mean.push_back(Mean(w.v, after[c], after[c + 1]));
    peaks.push_back(*std::max_element(w.v.begin() + after[c], w.v.begin() + after[c + 1]) -
                    m->equilibrium);
  }
  if (cycle_mean.size() >= 2) m->drift_per_s = Slope(cycle_mid_t, cycle_mean);
  double decrement_sum = 0;
  int decrement_count = 0;
  for (std::size_t k = 0; k + 1 < peaks.size(); ++k) {
    if (peaks[k] <= 0 || peaks[k + 1] <= 0) continue;
    decrement_sum += std::log(peaks[k] / peaks[k + 1]);
    ++decrement_count;
  }
  if (decrement_count > 0) m->log_decrement = decrement_sum / decrement_count;
}

void MeasureSettling(const Window& w, SignalMetrics* m) {
  const double range = m->maximum - m->minimum;
  const double band = m->final_value != 0 ? 0.02 * std::abs(m->final_value) : 0.02 * range;
  std::size_t first_inside = w.v.size() - 1;
  while (first_inside > 0 && std::abs(w.v[first_inside - 1] - m->final_value) <= band)
    --first_inside;
  const double duration = w.t.back() - w.t.front();
  if (w.t.back() - w.t[first_inside] >= 0.1 * duration) m->settling_time_s = w.t[first_inside];
}

}  // namespace

SignalMetrics MeasureSignal(const std::vector<double>& time_s, const std::vector<double>& values,
                            const SignalWindow& window) {
  const Window w = Select(time_s, values, window);
  SignalMetrics m;
  m.samples = w.t.size();
  m.window_start_s = w.t.front();
  m.window_end_s = w.t.back();
  const auto [lo, hi] = std::minmax_element(w.v.begin(), w.v.end());
  m.minimum = *lo;
  m.maximum = *hi;
  m.time_of_minimum_s = w.t[static_cast<std::size_t>(lo - w.v.begin())];
  m.time_of_maximum_s = w.t[static_cast<std::size_t>(hi - w.v.begin())];
  m.initial_value = w.v.front();
  m.final_value = w.v.back();
  const double centre = Mean(w.v, 0, w.v.size());
  m.equilibrium = centre;
  std::vector<double> crossing_t;
  std::vector<std::size_t> after;
  UpwardCrossings(w, centre, &crossing_t, &after);
  m.upward_crossings = crossing_t.size();
  if (crossing_t.size() >= 2) {
    std::vector<double> spacing(crossing_t.size() - 1);
    for (std::size_t i = 0; i + 1 < crossing_t.size(); ++i)
      spacing[i] = crossing_t[i + 1] - crossing_t[i];
    const double mean = Mean(spacing, 0, spacing.size());
    double var = 0;
    for (double s : spacing) var += (s - mean) * (s - mean);
    m.period_s = mean;
    m.period_spread_s = std::sqrt(var / static_cast<double>(spacing.size()));
    MeasureCycles(w, crossing_t, after, &m);
  } else {
    m.half_amplitude = (m.maximum - m.minimum) / 2;
  }
  MeasureSettling(w, &m);
  return m;
}

}  // namespace owval::compare
