#pragma once
// The peak of the power spectrum of a real series y (m samples) zero-padded to n samples (n the
// power of two >= 16 m), found without holding the padded series or its spectrum: memory is
// bounded by a constant block (the longest FFT), not by the series' length.
//
// With n = R L, bin k = R j + r (0 <= r < R, 0 <= j < L) of the n-point DFT of y (y_i = 0 for
// i >= m) is, writing i = a + b L (0 <= a < L) and using e^{-2 pi i j b L / L} = 1,
//   Y(R j + r) = sum_a e^{-2 pi i j a / L} x_r[a],
//   x_r[a] = sum_b y_{a + b L} e^{-2 pi i r (a + b L) / n}:
// residue r's bins are one L-point FFT (Eigen's FFT module) of y folded into L-sample blocks
// and modulated (Cooley & Tukey's index map with the zero input skipped, as in FFT pruning:
// Markel 1971, IEEE Trans. Audio Electroacoust. 19:305). A pass over the spectrum computes the R
// residues one at a time: O(R m + n log L) work, O(L) numbers held.
//   pass 1: the total power over bins 0..n/2 and the first bin of largest power (best);
//   pass 2: the troughs, exactly the nearest local minima either side of best that a walk over
//           the whole spectrum finds (each neighbouring pair of bins is compared once: residues
//           r - 1 and r, and R - 1 with 0 of the next j), and the power of the bins near best;
//   pass 3: only when a trough lies beyond those bins: the power between the troughs.
#include <cstddef>
#include <vector>

namespace owval::kinematics::internal {

struct PaddedPeak {
  std::size_t padded_length = 0;  // n
  std::size_t best = 0;           // first bin of largest power among bins 0..n/2
  // Troughs: lo the largest bin <= best with power[lo - 1] >= power[lo] (or 0), hi the smallest
  // bin >= best with power[hi + 1] >= power[hi] (or n/2): the nearest local minima.
  std::size_t lo = 0, hi = 0;
  double best_power = 0, lo_power = 0, hi_power = 0;  // |Y(k)|^2
  double total_power = 0;                             // over bins 0..n/2
  double between_power = 0;                           // over bins lo..hi
};

struct PaddedPeakOptions {
  // Longest FFT (a power of two): a longer series is folded into blocks this long. Memory is
  // about 60 bytes a sample of it (the folded block, its FFT and twiddles, three residues'
  // power): 2 MB. Smaller blocks cost time (R m multiplications a pass); tests use them to
  // exercise the folding on short series.
  std::size_t max_fft_length = std::size_t{1} << 15;
  // Bins kept either side of best in pass 2, so that the power between the troughs is summed in
  // bin order without a third pass; 0: 4 (n/m + 1), twice a pure tone's main lobe.
  std::size_t window_bins = 0;
};

// y of at least one sample.
PaddedPeak FindPaddedPeak(const std::vector<double>& y, const PaddedPeakOptions& options = {});

}  // namespace owval::kinematics::internal
