#pragma once
// Spectral peak of a sampled signal: FFT (Eigen's FFT module, zero-padded, streamed in blocks:
// padded_spectrum.hpp) for the coarse peak, then a least-squares sine fit
// y ~ a sin(2 pi f x) + b cos(2 pi f x) + c + d x refined by golden-section search around it, so
// that a pure sine's frequency is recovered to well under 1% even with one or two cycles in the
// window (where the bare FFT bin is coarse).
#include <vector>

namespace owval::kinematics::internal {

struct SpectralPeak {
  double frequency = 0;         // cycles per unit of x
  double amplitude = 0;         // of the fitted sine
  double coarse_frequency = 0;  // the padded FFT's peak bin
  // open-worm-analysis-toolbox's bandwidth rules (locomotion_bends.py): the nearest spectral
  // minima on either side of the peak (troughs) must stay below half the peak's magnitude, and
  // the energy between them must be at least half the total. bounded is false for a peak at DC.
  bool bounded = false;
  double trough_ratio = 0;  // larger trough magnitude over the peak magnitude
  double peak_energy_fraction = 0;
  double lowest_frequency = 0;  // 1 / span of x: one whole cycle in the window
};

// x evenly spaced (step dx), y of the same size (>= 4). Linear trend removed first. Returns false
// when the signal is constant.
bool FindSpectralPeak(const std::vector<double>& y, double dx, SpectralPeak* peak);

// Least-squares sine fit at a given frequency: amplitude sqrt(a^2 + b^2) and the residual sum.
struct SineFit {
  double amplitude = 0, residual = 0;
  std::vector<double> baseline;  // the fitted c + d x at each sample
};
SineFit FitSine(const std::vector<double>& y, double dx, double frequency);

// y minus its least-squares straight line.
std::vector<double> Detrended(const std::vector<double>& y);

// Frequency from sign changes of the detrended signal: (crossings - 1) / (2 * time between the
// first and last crossing), crossing times linearly interpolated. 0 when fewer than 3 crossings.
double ZeroCrossingFrequency(const std::vector<double>& y, double dx);

}  // namespace owval::kinematics::internal
