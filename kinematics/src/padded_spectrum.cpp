#include "padded_spectrum.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <unsupported/Eigen/FFT>

namespace owval::kinematics::internal {
namespace {

using Complex = std::complex<double>;

// e^{-2 pi i t / n} for 0 <= t < n (n a power of two) as the product of two entries of tables of
// about sqrt(n) each (t = high S + low, error ~2 ulp): a pass needs R m of them, too many for a
// sine and a cosine each.
class Twiddles {
 public:
  explicit Twiddles(std::size_t n) {
    while ((std::size_t{1} << (2 * shift_)) < n) ++shift_;
    const std::size_t s = std::size_t{1} << shift_;
    low_.resize(s);
    high_.resize((n + s - 1) / s);
    for (std::size_t t = 0; t < low_.size(); ++t) low_[t] = Unit(t, n);
    for (std::size_t h = 0; h < high_.size(); ++h) high_[h] = Unit(h * s, n);
  }
  Complex operator()(std::size_t t) const {
    return high_[t >> shift_] * low_[t & ((std::size_t{1} << shift_) - 1)];
  }

 private:
  static Complex Unit(std::size_t t, std::size_t n) {
    return std::polar(1.0, -2 * M_PI * static_cast<double>(t) / static_cast<double>(n));
  }
  std::size_t shift_ = 0;
  std::vector<Complex> low_, high_;
};

// The power of one residue's bins at a time (the header's formula).
class ResidueSpectra {
 public:
  ResidueSpectra(const std::vector<double>& y, std::size_t n, std::size_t fft_length)
      : y_(y),
        n_(n),
        length_(fft_length),
        twiddles_(n),
        folded_(fft_length),
        spectrum_(fft_length) {}

  std::size_t residues() const { return n_ / length_; }

  // power[j] = |Y(R j + r)|^2 for every j with R j + r <= n/2.
  void Power(std::size_t r, std::vector<double>* power) {
    std::fill(folded_.begin(), folded_.end(), Complex(0, 0));
    const std::size_t mask = n_ - 1;
    std::size_t phase = 0;  // r i mod n
    for (std::size_t i = 0; i < y_.size(); ++i, phase = (phase + r) & mask)
      folded_[i & (length_ - 1)] += y_[i] * twiddles_(phase);
    fft_.fwd(spectrum_.data(), folded_.data(), static_cast<Eigen::Index>(length_));
    power->resize((n_ / 2 - r) / residues() + 1);
    for (std::size_t j = 0; j < power->size(); ++j) (*power)[j] = std::norm(spectrum_[j]);
  }

 private:
  const std::vector<double>& y_;
  std::size_t n_, length_;
  Twiddles twiddles_;
  Eigen::FFT<double> fft_;
  std::vector<Complex> folded_, spectrum_;
};

// Pass 1: total power (each residue summed, then the residues: error ~ (L + R) eps, not n eps)
// and the first bin of largest power, as a walk in bin order finds it.
void BestAndTotal(ResidueSpectra& spectra, PaddedPeak* peak) {
  const std::size_t residues = spectra.residues();
  std::vector<double> power;
  peak->best_power = -1;
  for (std::size_t r = 0; r < residues; ++r) {
    spectra.Power(r, &power);
    double sum = 0;
    for (std::size_t j = 0; j < power.size(); ++j) {
      const std::size_t k = residues * j + r;
      sum += power[j];
      if (power[j] > peak->best_power || (power[j] == peak->best_power && k < peak->best)) {
        peak->best = k;
        peak->best_power = power[j];
      }
    }
    peak->total_power += sum;
  }
}

// The bins best - window .. best + window (within 0..n/2) while pass 2 runs.
struct Window {
  std::size_t first = 0;
  std::vector<double> power;
  bool Holds(std::size_t k) const { return k >= first && k - first < power.size(); }
};

// Pass 2: each neighbouring pair (k - 1, k) once, as the walks from best compare them.
void Troughs(ResidueSpectra& spectra, std::size_t half, Window* window, PaddedPeak* peak) {
  const std::size_t residues = spectra.residues(), best = peak->best;
  peak->lo = 0;
  peak->hi = half;
  auto pair = [&](std::size_t k, double before, double at) {
    if (k <= best && !(before < at)) peak->lo = std::max(peak->lo, k);
    if (k - 1 >= best && !(at < before)) peak->hi = std::min(peak->hi, k - 1);
  };
  std::vector<double> first, previous, current;
  for (std::size_t r = 0; r < residues; ++r) {
    spectra.Power(r, &current);
    for (std::size_t j = 0; j < current.size(); ++j)
      if (window->Holds(residues * j + r))
        window->power[residues * j + r - window->first] = current[j];
    if (r == 0)
      first = current;
    else
      for (std::size_t j = 0; j < current.size(); ++j)
        pair(residues * j + r, previous[j], current[j]);
    std::swap(previous, current);
  }
  // Residue R - 1 of j - 1 against residue 0 of j (R >= 8: R - 1 is not residue 0).
  for (std::size_t j = 1; j < first.size(); ++j) pair(residues * j, previous[j - 1], first[j]);
}

// Pass 3 (a trough beyond the window): the power of bins lo..hi.
void Between(ResidueSpectra& spectra, PaddedPeak* peak) {
  const std::size_t residues = spectra.residues();
  std::vector<double> power;
  peak->between_power = 0;
  for (std::size_t r = 0; r < residues; ++r) {
    spectra.Power(r, &power);
    double sum = 0;
    for (std::size_t j = 0; j < power.size(); ++j) {
      const std::size_t k = residues * j + r;
      if (k < peak->lo || k > peak->hi) continue;
      sum += power[j];
      if (k == peak->lo) peak->lo_power = power[j];
      if (k == peak->hi) peak->hi_power = power[j];
    }
    peak->between_power += sum;
  }
}

}  // namespace

PaddedPeak FindPaddedPeak(const std::vector<double>& y, const PaddedPeakOptions& options) {
  PaddedPeak peak;
  std::size_t n = 1;
  while (n < 16 * y.size()) n *= 2;
  peak.padded_length = n;
  // n >= 16 m, so an FFT of n/16 holds the series unfolded unless the block cap is smaller (at
  // least 2, a power of two: R = n / L is then a power of two >= 8).
  std::size_t length = 2;
  while (2 * length <= std::min(n / 16, options.max_fft_length)) length *= 2;
  ResidueSpectra spectra(y, n, length);
  BestAndTotal(spectra, &peak);

  const std::size_t half = n / 2;
  const std::size_t reach = options.window_bins > 0 ? options.window_bins : 4 * (n / y.size() + 1);
  Window window;
  window.first = peak.best - std::min(peak.best, reach);
  window.power.assign(std::min(half, peak.best + reach) - window.first + 1, 0.0);
  Troughs(spectra, half, &window, &peak);
  if (window.Holds(peak.lo) && window.Holds(peak.hi)) {
    // In bin order, as a walk over the whole spectrum sums it.
    for (std::size_t k = peak.lo; k <= peak.hi; ++k)
      peak.between_power += window.power[k - window.first];
    peak.lo_power = window.power[peak.lo - window.first];
    peak.hi_power = window.power[peak.hi - window.first];
  } else {
    Between(spectra, &peak);
  }
  return peak;
}

}  // namespace owval::kinematics::internal
