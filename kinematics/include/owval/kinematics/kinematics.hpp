#pragma once
// Worm kinematics from a skeleton series, after the definitions of Yemini et al. 2013 ("A
// database of Caenorhabditis elegans behavioral phenotypes", Nat. Methods 10:877) as implemented
// by openworm/open-worm-analysis-toolbox (own code here):
//  - every skeleton is resampled to 49 points evenly spaced along its arc length; body parts are
//    the toolbox's index ranges: head 0-7, midbody 16-32, tail 41-48;
//  - speed of a part: displacement of its centroid between t - w/2 and t + w/2 divided by the
//    elapsed time (w = 0.25 s for head and tail, 0.5 s for the midbody, as the toolbox), signed
//    + when the motion points from tail to head (forward), - otherwise; reported as the mean over
//    the frames whose window fits in the run;
//  - bend frequency: the midbody bend angle (the toolbox's partition, points 22-26, each the
//    angle between the edges to the points 4 before and after) over time; the peak of its
//    spectrum (FFT, zero-padded, refined by a least-squares sine fit) is accepted by the
//    toolbox's rules (locomotion_bends.py): not at 0 Hz, between 1/30 Hz and a 4-frame period,
//    the troughs either side below half the peak's magnitude, at least half of the energy between
//    them; owval measures one frequency over the whole run (the toolbox: per frame, in windows
//    between zero crossings), so it adds: at least one whole cycle in the run, at least 3 zero
//    crossings, and the zero-crossing frequency within 25% of the peak (the cross-check);
//  - wavelength: each skeleton rotated to its principal axes, its lateral offset resampled on an
//    even grid along the axis, the spectral peak along the body (refined the same way); capped at
//    twice the body length as the toolbox does; mean over frames;
//  - amplitude: the fitted sine's amplitude along the body (mean over frames), and the toolbox's
//    maximum amplitude (largest lateral distance from the principal axis; here from the best
//    straight line along it, which removes the axis' tilt when the body holds whole waves);
//  - crawling vs swimming: by bend frequency (above 1 Hz swimming; Fang-Yen et al. 2010, PNAS
//    107:20323: crawling ~0.3-0.5 Hz, swimming ~1.6-2 Hz), else by wavelength over body length
//    (above 1 swimming: ~1.5 swimming, ~0.65 crawling).
//
// Memory: the analysis streams (Analyser). The bend frequency's FFT needs the whole run's bend
// angle, and each frame's wave counts only when the body is not straight against the run's mean
// length (known at the end), so per frame it keeps 6 doubles (48 bytes, in deques: no spare
// capacity): arc length, midbody bend angle, and the wave's maximum offset,
// maximum offset from the fitted line, wavelength and amplitude. At Finish the bend angle's
// spectrum, zero-padded to 16x the frames, is computed in FFTs of at most 2^15 samples, never held
// whole: a transient of at most ~2 MB, plus the angles' contiguous copy, their detrended copy and a
// sine fit's baseline (8 bytes a frame each). The speeds need the part centroids of the frames
// within the longest window (0.5 s), kept only while a window is open. A skeleton series held whole
// costs its points (up to 99 at 16 bytes, ~1.6 kB a frame) and Analyse's resampled copy (49 points,
// 784 bytes).
#include <cstddef>
#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "owval/kinematics/skeleton.hpp"

namespace owval::kinematics {

struct Options {
  double head_tail_window_s = 0.25;              // toolbox's tip speed window
  double midbody_window_s = 0.5;                 // toolbox's body speed window
  double max_zero_crossing_disagreement = 0.25;  // FFT vs zero-crossing frequency, relative
  double min_frequency_hz = 1.0 / 30;            // toolbox: slower is no undulation
  double max_trough_ratio = 0.5;                 // toolbox's max_amplitude_pct_bandwidth
  double min_peak_energy_fraction = 0.5;         // toolbox's peak_energy_threshold
  double swimming_frequency_hz = 1.0;            // regime threshold
  // Below this range of the midbody bend angle the body is taken as not bending (a noise floor:
  // a straight body's angles are rounding noise, whose spectrum has a peak too).
  double min_bend_range_rad = 1e-3;
};

enum class Regime { kUndetermined, kCrawling, kSwimming };
const char* RegimeName(Regime regime);

struct Report {
  std::size_t frames = 0;
  double duration_s = 0;
  double length_mm = 0;  // mean arc length
  // Mean signed speeds (mm/s); empty when no frame's window fits in the run.
  std::optional<double> midbody_speed_mm_s, head_speed_mm_s, tail_speed_mm_s;
  std::optional<double> frequency_hz;                // accepted bend frequency
  std::optional<double> fft_frequency_hz;            // spectral peak, accepted or not
  std::optional<double> zero_crossing_frequency_hz;  // the cross-check
  std::string frequency_note;                        // why no frequency, when none
  std::optional<double> wavelength_mm;
  std::optional<double> amplitude_mm, max_amplitude_mm;
  Regime regime = Regime::kUndetermined;

  nlohmann::json ToJson() const;
  std::string ToText() const;
};

// The analysis frame by frame: Observe each frame in time order, then Finish (any number of
// times). Finish gives Analyse(series) of the frames observed, the same numbers bit for bit, and
// refuses what Analyse refuses (fewer than 2 frames, a skeleton of fewer than 2 points) with
// Analyse's InputError.
class Analyser {
 public:
  explicit Analyser(const Options& options = {});
  ~Analyser();
  Analyser(Analyser&&) noexcept;
  Analyser& operator=(Analyser&&) noexcept;

  void Observe(double time_s, const Skeleton& skeleton);
  Report Finish() const;

  std::size_t frames() const;
  // Frames whose part centroids are held for a speed window still open (bounded by the longest
  // window's frames, whatever the run's length).
  std::size_t window_frames() const;

  struct State;

 private:
  std::unique_ptr<State> state_;
};

// Analyser over the series' frames.
Report Analyse(const SkeletonSeries& series, const Options& options = {});
// Analyser over a worm trajectory read frame by frame (memory: one frame and the Analyser's);
// InputError when it is not a worm (as SkeletonsFromFrames).
Report AnalyseFrames(FrameSource& frames, const Options& options = {});

}  // namespace owval::kinematics
