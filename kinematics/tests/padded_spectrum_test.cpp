#include "padded_spectrum.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdint>
#include <cstdio>
#include <random>
#include <string>
#include <unsupported/Eigen/FFT>

#include "spectral.hpp"

namespace owval::kinematics::internal {
namespace {

// The oracle: the whole padded series through one FFT (Eigen's real FFT, as FindSpectralPeak
// did before it streamed), then the walks from the largest bin over the whole power spectrum.
PaddedPeak WholeSpectrumPeak(const std::vector<double>& y) {
  std::size_t n = 1;
  while (n < 16 * y.size()) n *= 2;
  std::vector<double> padded(n, 0.0);
  std::copy(y.begin(), y.end(), padded.begin());
  Eigen::FFT<double> fft;
  fft.SetFlag(Eigen::FFT<double>::HalfSpectrum);
  std::vector<std::complex<double>> spectrum;
  fft.fwd(spectrum, padded);
  std::vector<double> power(n / 2 + 1);
  for (std::size_t k = 0; k < power.size(); ++k) power[k] = std::norm(spectrum[k]);
  PaddedPeak p;
  p.padded_length = n;
  for (std::size_t k = 0; k < power.size(); ++k)
    if (power[k] > power[p.best]) p.best = k;
  p.lo = p.hi = p.best;
  while (p.lo > 0 && power[p.lo - 1] < power[p.lo]) --p.lo;
  while (p.hi + 1 < power.size() && power[p.hi + 1] < power[p.hi]) ++p.hi;
  for (std::size_t k = 0; k < power.size(); ++k) {
    p.total_power += power[k];
    if (k >= p.lo && k <= p.hi) p.between_power += power[k];
  }
  p.best_power = power[p.best];
  p.lo_power = power[p.lo];
  p.hi_power = power[p.hi];
  return p;
}

// Bins exactly; powers within 1e-12 of the total (a trough's power is small: its rounding is
// relative to the spectrum's scale, not to itself). Returns the largest power difference over the
// total (0 for silence).
double ExpectSamePeak(const PaddedPeak& got, const PaddedPeak& want, const std::string& what) {
  SCOPED_TRACE(what);
  EXPECT_EQ(got.padded_length, want.padded_length);
  EXPECT_EQ(got.best, want.best);
  EXPECT_EQ(got.lo, want.lo);
  EXPECT_EQ(got.hi, want.hi);
  const double scale = 1e-12 * want.total_power;
  EXPECT_NEAR(got.total_power, want.total_power, scale);
  EXPECT_NEAR(got.between_power, want.between_power, scale);
  EXPECT_NEAR(got.best_power, want.best_power, scale);
  EXPECT_NEAR(got.lo_power, want.lo_power, scale);
  EXPECT_NEAR(got.hi_power, want.hi_power, scale);
  double worst = 0;
  for (auto power : {&PaddedPeak::total_power, &PaddedPeak::between_power, &PaddedPeak::best_power,
                     &PaddedPeak::lo_power, &PaddedPeak::hi_power})
    worst = std::max(worst, std::abs(got.*power - want.*power));
  return want.total_power > 0 ? worst / want.total_power : worst;
}

void PrintWorst(double worst) {
  std::printf("largest power difference: %.2e of the total\n", worst);
}

// Uniform in [-1, 1), the same numbers on every platform (mt19937_64's raw output is specified).
std::vector<double> Noise(std::size_t m, std::uint64_t seed) {
  std::mt19937_64 random(seed);
  std::vector<double> y(m);
  for (double& v : y) v = 2.0 * static_cast<double>(random() >> 11) / 9007199254740992.0 - 1;
  return y;
}

std::vector<double> Sines(std::size_t m, double cycles, double second_cycles = 0) {
  std::vector<double> y(m);
  for (std::size_t i = 0; i < m; ++i) {
    const double x = static_cast<double>(i) / m;
    y[i] = std::sin(2 * M_PI * cycles * x + 0.3);
    if (second_cycles > 0) y[i] += 0.7 * std::sin(2 * M_PI * second_cycles * x + 1.1);
  }
  return y;
}

struct Signal {
  std::string name;
  std::vector<double> y;
};

std::vector<Signal> Signals() {
  std::vector<Signal> s;
  for (std::size_t m : {4, 5, 6, 7, 8, 49, 64, 100, 128, 199, 1000, 1024}) {
    const std::string tag = " m=" + std::to_string(m);
    s.push_back({"sine" + tag, Detrended(Sines(m, std::max(1.3, m / 9.7)))});
    s.push_back({"two sines" + tag, Detrended(Sines(m, std::max(1.1, m / 23.0), m / 5.1))});
    s.push_back({"noise" + tag, Detrended(Noise(m, m))});
    s.push_back({"raw noise" + tag, Noise(m, 1000 + m)});  // not detrended: its DC bin counts
  }
  // Silence: every bin ties, the first (0) is the largest and its own troughs.
  s.push_back({"silence", std::vector<double>(9, 0.0)});
  // The largest bin at DC (an offset) and at n/2 (alternating signs): the walks' ends.
  s.push_back({"offset", std::vector<double>(37, 2.5)});
  std::vector<double> alternating(40);
  for (std::size_t i = 0; i < alternating.size(); ++i) alternating[i] = i % 2 ? -1.0 : 1.0;
  s.push_back({"alternating", alternating});
  return s;
}

TEST(PaddedSpectrum, StreamedPeakMatchesTheWholePaddedFft) {
  double worst = 0;
  for (const Signal& s : Signals())
    worst = std::max(worst, ExpectSamePeak(FindPaddedPeak(s.y), WholeSpectrumPeak(s.y), s.name));
  PrintWorst(worst);
}

// Blocks shorter than the series: each residue folds y (2 to 250 blocks here).
TEST(PaddedSpectrum, FoldedIntoShortBlocksMatchesTheWholePaddedFft) {
  double worst = 0;
  for (const Signal& s : Signals())
    for (std::size_t block : {2, 4, 8}) {
      PaddedPeakOptions o;
      o.max_fft_length = block;
      worst = std::max(worst, ExpectSamePeak(FindPaddedPeak(s.y, o), WholeSpectrumPeak(s.y),
                                             s.name + " block " + std::to_string(block)));
    }
  PrintWorst(worst);
}

// A window of one bin either side of the peak cannot hold the troughs: the third pass sums the
// power between them, in residue order.
TEST(PaddedSpectrum, TroughsBeyondTheWindowMatchTheWholePaddedFft) {
  double worst = 0;
  for (const Signal& s : Signals()) {
    PaddedPeakOptions o;
    o.window_bins = 1;
    o.max_fft_length = 4;
    worst = std::max(worst, ExpectSamePeak(FindPaddedPeak(s.y, o), WholeSpectrumPeak(s.y),
                                           s.name + " window 1"));
  }
  PrintWorst(worst);
}

// A series longer than the default block (2^15): folded by default, n = 2^20.
TEST(PaddedSpectrum, LongSeriesFoldedByDefaultMatchesTheWholePaddedFft) {
  std::vector<double> y = Sines(40000, 123.4, 310.2);
  const std::vector<double> noise = Noise(y.size(), 7);
  for (std::size_t i = 0; i < y.size(); ++i) y[i] += 0.5 * noise[i];
  PrintWorst(ExpectSamePeak(FindPaddedPeak(Detrended(y)), WholeSpectrumPeak(Detrended(y)),
                            "40000 samples"));
}

// Parseval for a real series: bins 0..n/2 hold (n sum y^2 + |Y(0)|^2 + |Y(n/2)|^2) / 2.
TEST(PaddedSpectrum, TotalPowerIsParsevals) {
  for (const Signal& s : Signals())
    for (std::size_t block : {std::size_t{4}, std::size_t{1} << 15}) {
      PaddedPeakOptions o;
      o.max_fft_length = block;
      const PaddedPeak p = FindPaddedPeak(s.y, o);
      double energy = 0, dc = 0, nyquist = 0;
      for (std::size_t i = 0; i < s.y.size(); ++i) {
        energy += s.y[i] * s.y[i];
        dc += s.y[i];
        nyquist += i % 2 ? -s.y[i] : s.y[i];
      }
      const double n = p.padded_length, total = (n * energy + dc * dc + nyquist * nyquist) / 2;
      EXPECT_NEAR(p.total_power, total, 1e-12 * total) << s.name << " block " << block;
    }
}

// A pure tone: its peak bin is the padded bin nearest the tone's frequency, its troughs the
// main lobe's first nulls, about n/m bins either side.
TEST(PaddedSpectrum, PureToneTroughsAreTheMainLobesNulls) {
  const std::size_t m = 100;
  const PaddedPeak p = FindPaddedPeak(Sines(m, 10));  // n = 2048: tone at bin 204.8
  EXPECT_EQ(p.padded_length, 2048u);
  EXPECT_NEAR(static_cast<double>(p.best), 204.8, 1.0);
  EXPECT_NEAR(static_cast<double>(p.best - p.lo), 2048.0 / m, 2.0);
  EXPECT_NEAR(static_cast<double>(p.hi - p.best), 2048.0 / m, 2.0);
  EXPECT_GT(p.between_power, 0.8 * p.total_power);
}

// FindSpectralPeak's bandwidth numbers (the toolbox's rules) from the streamed peak are the
// whole spectrum's: the coarse peak exactly, the ratios within 1e-12.
TEST(PaddedSpectrum, SpectralPeakBandwidthIsTheWholeSpectrums) {
  for (std::size_t m : {6, 49, 199, 1990}) {
    const std::vector<double> y = Sines(m, std::max(1.5, m / 17.0), m / 6.0);
    SpectralPeak peak;
    ASSERT_TRUE(FindSpectralPeak(y, 0.003, &peak));
    const PaddedPeak whole = WholeSpectrumPeak(Detrended(y));
    SCOPED_TRACE("m=" + std::to_string(m));
    EXPECT_EQ(peak.coarse_frequency, whole.best * (1.0 / (whole.padded_length * 0.003)));
    EXPECT_TRUE(peak.bounded);
    const double ratio = std::sqrt(std::max(whole.lo_power, whole.hi_power) / whole.best_power);
    EXPECT_NEAR(peak.trough_ratio, ratio, 1e-12 * ratio);
    const double fraction = whole.between_power / whole.total_power;
    EXPECT_NEAR(peak.peak_energy_fraction, fraction, 1e-12 * fraction);
  }
}

}  // namespace
}  // namespace owval::kinematics::internal
