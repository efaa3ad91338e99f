#include "spectral.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <numeric>

#include "padded_spectrum.hpp"

namespace owval::kinematics::internal {
namespace {

// The toolbox's bandwidth of the peak: the nearest local minima of the magnitude on each side
// (PaddedPeak's troughs). A side that decays to the spectrum's end is bounded there (after
// detrending, the DC bin is near zero); only a peak at DC itself has no bandwidth.
void Bandwidth(const PaddedPeak& padded, SpectralPeak* peak) {
  peak->bounded = padded.best > 0;
  peak->trough_ratio = std::sqrt(std::max(padded.lo_power, padded.hi_power) / padded.best_power);
  peak->peak_energy_fraction =
      padded.total_power > 0 ? padded.between_power / padded.total_power : 0;
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
  fit.baseline.reserve(y.size());  // 8 bytes a sample, not up to twice that as it grows
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
  // The padded spectrum's peak bin and troughs, streamed: memory bounded whatever y's length.
  const PaddedPeak padded = FindPaddedPeak(y);
  const std::size_t n = padded.padded_length, best = padded.best;
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
  Bandwidth(padded, peak);
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
