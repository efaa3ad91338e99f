#include "owval/kinematics/kinematics.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <deque>
#include <numeric>
#include <sstream>

#include "owval/base/errors.hpp"
#include "owval/kinematics/midline.hpp"
#include "spectral.hpp"
#include "speed_windows.hpp"

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

void BendFrequency(const std::vector<double>& angle, double dt, const Options& o, Report* r) {
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

// One frame's wave along the body, before the run's mean length says whether the body is
// straight (kept per frame: the Analyser's 4 of its 6 doubles a frame).
struct FrameWave {
  double max_offset_mm = 0;    // from the principal axis
  double max_from_fit_mm = 0;  // from the straight line fitted with the wave
  double wavelength_mm = 0;    // 1 / the spectral peak along the body; 0: no peak
  double amplitude_mm = 0;     // the fitted sine's
};

FrameWave WaveOf(const Skeleton& body) {
  FrameWave w;
  double dx = 0;
  const std::vector<double> y = AlongPrincipalAxis(body, &dx, &w.max_offset_mm);
  internal::SpectralPeak peak;
  if (!(dx > 0) || !internal::FindSpectralPeak(y, dx, &peak) || !(peak.frequency > 0)) return w;
  // The principal axis tilts when the body holds a whole number of waves: the maximum offset
  // is taken from the straight line fitted with the wave instead.
  const internal::SineFit fit = internal::FitSine(y, dx, peak.frequency);
  for (std::size_t i = 0; i < y.size(); ++i)
    w.max_from_fit_mm = std::max(w.max_from_fit_mm, std::abs(y[i] - fit.baseline[i]));
  w.wavelength_mm = 1.0 / peak.frequency;
  w.amplitude_mm = peak.amplitude;
  return w;
}

// Means over the frames, summed in frame order; a straight body (offset within 1e-4 of the
// mean length) holds no wave to measure.
void WaveShape(const std::deque<FrameWave>& frames, double length_mm, Report* r) {
  double wavelength = 0, amplitude = 0, max_amplitude = 0;
  std::size_t waves = 0;
  for (const FrameWave& w : frames) {
    max_amplitude += w.max_offset_mm;
    if (w.max_offset_mm <= 1e-4 * length_mm || w.wavelength_mm == 0) continue;
    max_amplitude += w.max_from_fit_mm - w.max_offset_mm;
    wavelength += std::min(w.wavelength_mm, 2 * length_mm);
    amplitude += w.amplitude_mm;
    ++waves;
  }
  r->max_amplitude_mm = max_amplitude / frames.size();
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

struct Analyser::State {
  explicit State(const Options& o) : options(o), speeds(o.head_tail_window_s, o.midbody_window_s) {}
  Options options;
  internal::SpeedWindows speeds;
  std::size_t frames = 0;
  double first_time_s = 0, last_time_s = 0;
  bool short_skeleton = false;  // a frame with fewer than 2 points: Finish refuses the run
  // Per frame (the run's means and the bend angle's spectrum need them all). Deques, not vectors:
  // a vector grown by doubling holds spare capacity and copies itself as it grows (a 39,801-frame
  // run peaked 1.4 MB higher).
  std::deque<double> length_mm, bend_rad;
  std::deque<FrameWave> waves;
};

Analyser::Analyser(const Options& options) : state_(std::make_unique<State>(options)) {}
Analyser::~Analyser() = default;
Analyser::Analyser(Analyser&&) noexcept = default;
Analyser& Analyser::operator=(Analyser&&) noexcept = default;

std::size_t Analyser::frames() const { return state_->frames; }
std::size_t Analyser::window_frames() const { return state_->speeds.held_frames(); }

void Analyser::Observe(double time_s, const Skeleton& skeleton) {
  State& s = *state_;
  if (s.frames++ == 0) s.first_time_s = time_s;
  s.last_time_s = time_s;
  if (skeleton.size() < 2) s.short_skeleton = true;
  if (s.short_skeleton) return;
  const Skeleton body = ResampleByArcLength(skeleton);
  s.length_mm.push_back(ArcLength(skeleton));
  s.bend_rad.push_back(MidbodyBendAngle(body));
  s.waves.push_back(WaveOf(body));
  s.speeds.Observe(
      {time_s, Centroid(body, kHead), Centroid(body, kMidbody), Centroid(body, kTail)});
}

Report Analyser::Finish() const {
  const State& s = *state_;
  if (s.frames < 2) throw InputError("kinematics need at least 2 frames with one skeleton each");
  if (s.short_skeleton) throw InputError("skeleton needs at least 2 points");
  const Options& o = s.options;
  Report r;
  r.frames = s.frames;
  r.duration_s = s.last_time_s - s.first_time_s;
  for (double length : s.length_mm) r.length_mm += length / s.frames;
  r.midbody_speed_mm_s = s.speeds.MeanSpeed(internal::BodyPart::kMidbody);
  r.head_speed_mm_s = s.speeds.MeanSpeed(internal::BodyPart::kHead);
  r.tail_speed_mm_s = s.speeds.MeanSpeed(internal::BodyPart::kTail);
  // The spectrum takes a contiguous series: a transient copy, 8 bytes a frame.
  BendFrequency({s.bend_rad.begin(), s.bend_rad.end()}, r.duration_s / (s.frames - 1), o, &r);
  WaveShape(s.waves, r.length_mm, &r);
  if (r.frequency_hz)
    r.regime = *r.frequency_hz > o.swimming_frequency_hz ? Regime::kSwimming : Regime::kCrawling;
  else if (r.wavelength_mm && r.length_mm > 0)
    r.regime = *r.wavelength_mm > r.length_mm ? Regime::kSwimming : Regime::kCrawling;
  return r;
}

Report Analyse(const SkeletonSeries& series, const Options& options) {
  if (series.time_s.size() != series.skeletons.size() || series.time_s.size() < 2)
    throw InputError("kinematics need at least 2 frames with one skeleton each");
  Analyser analyser(options);
  for (std::size_t f = 0; f < series.time_s.size(); ++f)
    analyser.Observe(series.time_s[f], series.skeletons[f]);
  return analyser.Finish();
}

Report AnalyseFrames(FrameSource& frames, const Options& options) {
  Analyser analyser(options);
  ForEachFrameSkeleton(
      frames, [&](double time_s, const Skeleton& skeleton) { analyser.Observe(time_s, skeleton); });
  return analyser.Finish();
}

}  // namespace owval::kinematics
