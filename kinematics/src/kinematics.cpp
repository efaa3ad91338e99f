#include "owval/kinematics/kinematics.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

#include "owval/base/errors.hpp"
#include "spectral.hpp"

namespace owval::kinematics {
namespace {

struct Part {
  int first, last;  // inclusive indices into the 49-point skeleton
};
constexpr Part kHead{0, 7}, kMidbody{16, 32}, kTail{41, 48};

Point2 Centroid(const Skeleton& s, Part p) {
  Point2 c{0, 0};
  for (int i = p.first; i <= p.last; ++i) c = {c[0] + s[i][0], c[1] + s[i][1]};
  const double n = p.last - p.first + 1;
  return {c[0] / n, c[1] / n};
}

// Mean signed speed of a part's centroid over a window of width window_s centred on each frame.
std::optional<double> MeanSpeed(const SkeletonSeries& s, const std::vector<Skeleton>& body,
                                Part part, double window_s) {
  double sum = 0;
  std::size_t used = 0;
  const std::size_t n = body.size();
  for (std::size_t i = 0, j = 0; i < n; ++i) {
    // j: the first frame at or after t_i + window; i's window is [t_i, t_j], centred at its middle.
    while (j < n && s.time_s[j] < s.time_s[i] + window_s - 1e-9) ++j;
    if (j >= n) break;
    const Point2 a = Centroid(body[i], part), b = Centroid(body[j], part);
    const Point2 d{b[0] - a[0], b[1] - a[1]};
    // Forward: along the tail-to-head direction at the middle of the window.
    const Skeleton& mid = body[(i + j) / 2];
    const Point2 h = Centroid(mid, kHead), t = Centroid(mid, kTail);
    const double along = d[0] * (h[0] - t[0]) + d[1] * (h[1] - t[1]);
    const double speed = std::hypot(d[0], d[1]) / (s.time_s[j] - s.time_s[i]);
    sum += along < 0 ? -speed : speed;
    ++used;
  }
  if (used == 0) return std::nullopt;
  return sum / used;
}

// Mean bend angle (radians, signed) over the toolbox's midbody bend partition, points 22-26 of
// the 49: at each point the angle between the edges to the points kBendEdge before and after it
// (the toolbox measures bends over edges of about 1/12 of the body: 4 of 48 segments).
constexpr int kBendEdge = 4;
constexpr Part kMidbodyBend{22, 26};

double MidbodyBendAngle(const Skeleton& s) {
  double sum = 0;
  for (int i = kMidbodyBend.first; i <= kMidbodyBend.last; ++i) {
    const Point2 u{s[i][0] - s[i - kBendEdge][0], s[i][1] - s[i - kBendEdge][1]};
    const Point2 v{s[i + kBendEdge][0] - s[i][0], s[i + kBendEdge][1] - s[i][1]};
    sum += std::atan2(u[0] * v[1] - u[1] * v[0], u[0] * v[0] + u[1] * v[1]);
  }
  return sum / (kMidbodyBend.last - kMidbodyBend.first + 1);
}

// Why the spectral peak is rejected, or "" when it is accepted.
std::string Rejection(const internal::SpectralPeak& peak, double zc, double duration_s,
                      double max_frequency_hz, const Options& o) {
  std::ostringstream why;
  if (!peak.bounded)
    why << "spectral peak at 0 Hz (no undulation)";
  else if (peak.coarse_frequency < o.min_frequency_hz || peak.coarse_frequency > max_frequency_hz)
    why << "spectral peak " << peak.coarse_frequency << " Hz outside " << o.min_frequency_hz << ".."
        << max_frequency_hz << " Hz";
  else if (peak.trough_ratio > o.max_trough_ratio)
    why << "peak unclear: a trough beside it reaches " << peak.trough_ratio
        << " of its height (max " << o.max_trough_ratio << ")";
  else if (peak.peak_energy_fraction < o.min_peak_energy_fraction)
    why << "peak weak: it holds " << peak.peak_energy_fraction << " of the energy (min "
        << o.min_peak_energy_fraction << ")";
  else if (peak.frequency * duration_s < 1)
    why << "run holds less than one cycle (" << peak.frequency * duration_s
        << " cycles at the spectral peak)";
  else if (zc <= 0)
    why << "fewer than 3 zero crossings of the bend angle";
  else if (std::abs(zc - peak.frequency) > o.max_zero_crossing_disagreement * peak.frequency)
    why << "zero-crossing frequency " << zc << " Hz disagrees with the spectral peak "
        << peak.frequency << " Hz";
  return why.str();
}

void BendFrequency(const SkeletonSeries& s, const std::vector<Skeleton>& body, const Options& o,
                   Report* r) {
  std::vector<double> angle;
  for (const Skeleton& b : body) angle.push_back(MidbodyBendAngle(b));
  const double dt = (s.time_s.back() - s.time_s.front()) / (s.time_s.size() - 1);
  const auto [lo, hi] = std::minmax_element(angle.begin(), angle.end());
  internal::SpectralPeak peak;
  if (*hi - *lo < o.min_bend_range_rad || !internal::FindSpectralPeak(angle, dt, &peak)) {
    r->frequency_note = "midbody does not bend";
    return;
  }
  r->fft_frequency_hz = peak.frequency;
  const double zc = internal::ZeroCrossingFrequency(angle, dt);
  if (zc > 0) r->zero_crossing_frequency_hz = zc;
  // The toolbox's highest frequency: a 4-frame period (fps / 4).
  r->frequency_note = Rejection(peak, zc, r->duration_s, 0.25 / dt, o);
  if (r->frequency_note.empty()) r->frequency_hz = peak.frequency;
}

// Lateral offsets of a skeleton on an even grid along its principal axis (grid step in *dx_mm).
std::vector<double> AlongPrincipalAxis(const Skeleton& s, double* dx_mm, double* max_offset_mm) {
  Eigen::MatrixXd p(s.size(), 2);
  for (std::size_t i = 0; i < s.size(); ++i) p.row(i) << s[i][0], s[i][1];
  p.rowwise() -= p.colwise().mean();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(p.transpose() * p);
  const Eigen::MatrixXd r = p * eig.eigenvectors();  // column 1: major axis, column 0: minor
  std::vector<std::pair<double, double>> xy;
  for (Eigen::Index i = 0; i < r.rows(); ++i) xy.emplace_back(r(i, 1), r(i, 0));
  std::sort(xy.begin(), xy.end());
  const std::size_t n = s.size();
  *dx_mm = (xy.back().first - xy.front().first) / (n - 1);
  std::vector<double> y(n);
  for (std::size_t k = 0, j = 1; k < n; ++k) {
    const double x = xy.front().first + *dx_mm * k;
    while (j + 1 < n && xy[j].first < x) ++j;
    const double span = xy[j].first - xy[j - 1].first;
    const double w = span > 0 ? std::clamp((x - xy[j - 1].first) / span, 0.0, 1.0) : 0.0;
    y[k] = xy[j - 1].second + w * (xy[j].second - xy[j - 1].second);
  }
  *max_offset_mm = 0;
  for (double v : internal::Detrended(y)) *max_offset_mm = std::max(*max_offset_mm, std::abs(v));
  return y;
}

void WaveShape(const std::vector<Skeleton>& body, double length_mm, Report* r) {
  double wavelength = 0, amplitude = 0, max_amplitude = 0;
  std::size_t waves = 0;
  for (const Skeleton& s : body) {
    double dx = 0, max_offset = 0;
    const std::vector<double> y = AlongPrincipalAxis(s, &dx, &max_offset);
    max_amplitude += max_offset;
    if (max_offset <= 1e-4 * length_mm) continue;  // straight: no wave to measure
    internal::SpectralPeak peak;
    if (!(dx > 0) || !internal::FindSpectralPeak(y, dx, &peak) || !(peak.frequency > 0)) continue;
    // The principal axis tilts when the body holds a whole number of waves: the maximum offset
    // is taken from the straight line fitted with the wave instead.
    const internal::SineFit fit = internal::FitSine(y, dx, peak.frequency);
    double max_from_fit = 0;
    for (std::size_t i = 0; i < y.size(); ++i)
      max_from_fit = std::max(max_from_fit, std::abs(y[i] - fit.baseline[i]));
    max_amplitude += max_from_fit - max_offset;
    wavelength += std::min(1.0 / peak.frequency, 2 * length_mm);
    amplitude += peak.amplitude;
    ++waves;
  }
  r->max_amplitude_mm = max_amplitude / body.size();
  if (waves == 0) return;
  r->wavelength_mm = wavelength / waves;
  r->amplitude_mm = amplitude / waves;
}

}  // namespace

const char* RegimeName(Regime regime) {
  switch (regime) {
    case Regime::kCrawling:
      return "crawling";
    case Regime::kSwimming:
      return "swimming";
    default:
      return "undetermined";
  }
}

Report Analyse(const SkeletonSeries& s, const Options& o) {
  if (s.time_s.size() != s.skeletons.size() || s.time_s.size() < 2)
    throw InputError("kinematics need at least 2 frames with one skeleton each");
  Report r;
  r.frames = s.time_s.size();
  r.duration_s = s.time_s.back() - s.time_s.front();
  std::vector<Skeleton> body;
  for (const Skeleton& k : s.skeletons) {
    body.push_back(ResampleByArcLength(k));
    r.length_mm += ArcLength(k) / s.skeletons.size();
  }
  r.midbody_speed_mm_s = MeanSpeed(s, body, kMidbody, o.midbody_window_s);
  r.head_speed_mm_s = MeanSpeed(s, body, kHead, o.head_tail_window_s);
  r.tail_speed_mm_s = MeanSpeed(s, body, kTail, o.head_tail_window_s);
  BendFrequency(s, body, o, &r);
  WaveShape(body, r.length_mm, &r);
  if (r.frequency_hz)
    r.regime = *r.frequency_hz > o.swimming_frequency_hz ? Regime::kSwimming : Regime::kCrawling;
  else if (r.wavelength_mm && r.length_mm > 0)
    r.regime = *r.wavelength_mm > r.length_mm ? Regime::kSwimming : Regime::kCrawling;
  return r;
}

}  // namespace owval::kinematics
