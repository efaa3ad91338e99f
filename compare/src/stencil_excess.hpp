#pragma once
// acceleration.worst_stencil's measure, streamed (pair_reducer.hpp): at each stencil, by how much
// one run's median acceleration exceeds the other run's largest within kStencilWindow stencils
// either side, over that largest or over the reference's mean over the run, whichever is larger.
//
// The mean is only known at the end, so each stencil's excess cannot be divided as it comes.
// Memory stays bounded by the window instead of growing with the run: an excess e over the
// neighbourhood's largest median M is worth e / max(M, mean), which grows with e and shrinks
// with M whatever the mean. A pair that an earlier one matches in both (excess at least as
// large, largest at most as large) can never be the first worst and is dropped as it comes; an
// earlier pair that a later one beats in both is dropped too. What remains is a staircase: 1-8
// pairs on demo1, its 1 s run, test_energy, the worm and one_sprig. Past kMaxKept pairs the two
// whose largest medians are closest merge into the larger excess over the smaller largest: that
// can only overstate the worst (by their ratio: 1.5% where 20,000 pairs' largests span four
// decades), never hide one. Up to kMaxKept, the worst is exactly the one every stencil kept and
// judged at the end would give.
#include <array>
#include <cstddef>
#include <vector>

namespace owval::compare::internal {

// One run's median acceleration at a stencil exceeding the other's nearby ones.
struct StencilExcess {
  double value = -1;                // excess over max(largest nearby, mean); see Worst
  std::size_t reference_frame = 0;  // the stencil's middle reference frame
  double median[2] = {0, 0};        // the stencil's medians (reference, candidate), cu/s^2
};

class StencilExcesses {
 public:
  static constexpr std::size_t kStencilWindow = 5;  // stencils either side
  static constexpr std::size_t kMaxKept = 1024;

  // The next stencil, in time order: its middle reference frame and both runs' medians.
  void Push(std::size_t reference_frame, double reference_median, double candidate_median);

  // The first stencil at which an excess is largest once divided by max(largest nearby, mean),
  // with an excess of zero worth zero and a NaN worth infinity (a median that overflowed). Its
  // value is -1 before any stencil.
  StencilExcess Worst(double mean) const;

  std::size_t kept() const { return kept_.size(); }

 private:
  struct Stencil {
    std::size_t reference_frame;
    double median[2];
  };
  struct Pair {
    double excess;   // max(0, a run's median - the other run's largest nearby), cu/s^2
    double largest;  // the other run's largest median within the window, cu/s^2
    Stencil stencil;
  };
  // Both runs' pairs at stencil `i`, whose window ends at stencil `last` (pushed already).
  std::array<Pair, 2> PairsAt(std::size_t i, std::size_t last) const;
  void Keep(const Pair& pair);
  void MergeClosest();

  std::array<Stencil, 2 * kStencilWindow + 1> ring_{};  // stencil k at k % size
  std::size_t pushed_ = 0;
  std::vector<Pair> kept_;  // in time order
};

}  // namespace owval::compare::internal
