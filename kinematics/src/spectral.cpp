#include "spectral.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <complex>
#include <numeric>
#include <unsupported/Eigen/FFT>

namespace owval::kinematics::internal {
namespace {

// Power spectrum of y zero-padded to at least 16x its length (a power of two).
std::vector<double> PaddedPower(const std::vector<double>& y) {
  std::size_t n = 1;
  while (n < 16 * y.size()) n *= 2;
  std::vector<double> padded(n, 0.0);
  std::copy(y.begin(), y.end(), padded.begin());
  // Only the bins 0..n/2 are used: HalfSpectrum keeps the FFT from mirroring the other half
  // into a second n/2 complex values (the kept bins are the same numbers; for a run's bend angle,
  // padded to 16x its frames, that half was 128 bytes a frame).
  Eigen::FFT<double> fft;
  fft.SetFlag(Eigen::FFT<double>::HalfSpectrum);
  std::vector<std::complex<double>> spectrum;
  fft.fwd(spectrum, padded);
  std::vector<double> power(n / 2 + 1);
  for (std::size_t k = 0; k < power.size(); ++k) power[k] = std::norm(spectrum[k]);
  return power;
}

// The toolbox's bandwidth of the peak: nearest local minima of the magnitude on each side.
void Bandwidth(const std::vector<double>& power, std::size_t best, SpectralPeak* peak) {
  std::size_t lo = best, hi = best;
  while (lo > 0 && power[lo - 1] < power[lo]) --lo;
  while (hi + 1 < power.size() && power[hi + 1] < power[hi]) ++hi;
  // A side that decays to the spectrum's end is bounded there (after detrending, the DC bin is
  // near zero); only a peak at DC itself has no bandwidth.
  peak->bounded = best > 0;
  peak->trough_ratio = std::sqrt(std::max(power[lo], power[hi]) / power[best]);
  double total = 0, between = 0;
  for (std::size_t k = 0; k < power.size(); ++k) {
    total += power[k];
    if (k >= lo && k <= hi) between += power[k];
  }
  peak->peak_energy_fraction = total > 0 ? between / total : 0;
}

}  // namespace

// y minus its least-squares line: the rotation to the principal axis leaves a tilt when the body
// holds a whole number of waves, and a slow drift of a bend angle is no undulation.
std::vector<double> Detrended(const std::vector<double>& y) {
  const double n = y.size(), mx = (n - 1) / 2;
  const double my = std::accumulate(y.begin(), y.end(), 0.0) / n;
  double sxy = 0, sxx = 0;
  for (std::size_t i = 0; i < y.size(); ++i) {
    sxy += (i - mx) * (y[i] - my);
    sxx += (i - mx) * (i - mx);
  }
  const double slope = sxx > 0 ? sxy / sxx : 0;
  std::vector<double> c(y.size());
  for (std::size_t i = 0; i < y.size(); ++i) c[i] = y[i] - my - slope * (i - mx);
  return c;
}

SineFit FitSine(const std::vector<double>& y, double dx, double frequency) {
  Eigen::Matrix4d normal = Eigen::Matrix4d::Zero();
  Eigen::Vector4d rhs = Eigen::Vector4d::Zero();
  const double mid = 0.5 * (y.size() - 1);
  for (std::size_t i = 0; i < y.size(); ++i) {
    const double phase = 2 * M_PI * frequency * dx * i;
    const Eigen::Vector4d basis(std::sin(phase), std::cos(phase), 1.0, (i - mid) / mid);
    normal += basis * basis.transpose();
    rhs += basis * y[i];
  }
  const Eigen::Vector4d c = normal.ldlt().solve(rhs);
  SineFit fit;
  fit.amplitude = std::hypot(c[0], c[1]);
  for (std::size_t i = 0; i < y.size(); ++i) fit.baseline.push_back(c[2] + c[3] * (i - mid) / mid);
  for (std::size_t i = 0; i < y.size(); ++i) {
    const double phase = 2 * M_PI * frequency * dx * i;
    const double r =
        y[i] - (c[0] * std::sin(phase) + c[1] * std::cos(phase) + c[2] + c[3] * (i - mid) / mid);
    fit.residual += r * r;
  }
  return fit;
}

bool FindSpectralPeak(const std::vector<double>& raw, double dx, SpectralPeak* peak) {
  if (raw.size() < 4 || !(dx > 0)) return false;
  const std::vector<double> y = Detrended(raw);
  double energy = 0;
  for (double v : y) energy += v * v;
  if (!(energy > 0)) return false;
  const std::vector<double> power = PaddedPower(y);
  const std::size_t n = 2 * (power.size() - 1);
  std::size_t best = 0;
  for (std::size_t k = 0; k < power.size(); ++k)
    if (power[k] > power[best]) best = k;
  const double bin = 1.0 / (n * dx);
  // Golden-section search of the sine fit's residual within two padded bins of the peak.
  double lo = std::max((best - 2.0) * bin, 0.25 * bin), hi = (best + 2.0) * bin;
  const double g = 0.5 * (std::sqrt(5.0) - 1);
  for (int it = 0; it < 80; ++it) {
    const double a = hi - g * (hi - lo), b = lo + g * (hi - lo);
    if (FitSine(y, dx, a).residual < FitSine(y, dx, b).residual)
      hi = b;
    else
      lo = a;
  }
  peak->frequency = 0.5 * (lo + hi);
  peak->amplitude = FitSine(y, dx, peak->frequency).amplitude;
  peak->coarse_frequency = best * bin;
  Bandwidth(power, best, peak);
  peak->lowest_frequency = 1.0 / ((y.size() - 1) * dx);
  return true;
}

double ZeroCrossingFrequency(const std::vector<double>& raw, double dx) {
  const std::vector<double> y = Detrended(raw);
  std::vector<double> crossings;
  for (std::size_t i = 1; i < y.size(); ++i) {
    if ((y[i - 1] < 0) != (y[i] < 0)) {
      const double w = y[i - 1] / (y[i - 1] - y[i]);
      crossings.push_back(dx * (i - 1 + w));
    }
  }
  if (crossings.size() < 3) return 0;
  return (crossings.size() - 1) / (2 * (crossings.back() - crossings.front()));
}

}  // namespace owval::kinematics::internal
