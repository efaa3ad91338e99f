#pragma once
// The candidate's frames against the reference's to the files' printed precision: where it
// starts and where its walls stand (InitialState), and frames written twice (StaleFrames).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "owval/trajectory/frame_source.hpp"

namespace owval::compare::internal {

// The candidate's state at the reference's first frame, particle for particle: a run of the same
// configuration starts where the reference starts (Sibernetic logs its frame 0 after step 0,
// which moves nothing but the membrane pass; owval's backends log the same state), so the two
// agree to the files' printed precision, and a candidate that starts elsewhere is another
// experiment. Each coordinate's allowance is the rounding of two prints at 6 significant digits,
// 1e-5 of its magnitude, plus float32's at the box's scale near zero; the value is the worst
// coordinate's difference in those allowances. The same measure holds the walls at every paired
// frame (GateBoundaryFixed): boundary particles are never integrated.
struct InitialState {
  bool observed = false;
  double worst = 0;  // |x_cand - x_ref| / allowance, worst coordinate
  std::size_t particle = 0;
  int axis = 0;
  double reference_cu = 0, candidate_cu = 0;

  std::size_t reference_frame = 0;  // where the worst coordinate is

  // Every particle at this pair of frames (the reference's first).
  void Observe(const FrameRef& ref, const FrameRef& cand, double box_scale_cu) {
    for (std::size_t p = 0; p < ref.trajectory.particle_count(); ++p)
      ObserveParticle(ref, cand, p, box_scale_cu);
  }
  // `members` only, at the pair of frames whose reference frame is `reference_frame_index`.
  void Observe(const FrameRef& ref, const FrameRef& cand, double box_scale_cu,
               const std::vector<std::size_t>& members, std::size_t reference_frame_index) {
    const double before = worst;
    for (std::size_t p : members) ObserveParticle(ref, cand, p, box_scale_cu);
    if (worst > before) reference_frame = reference_frame_index;
  }
  void ObserveParticle(const FrameRef& ref, const FrameRef& cand, std::size_t p,
                       double box_scale_cu) {
    observed = true;
    const float* x = ref.trajectory.position(ref.frame, p);
    const float* y = cand.trajectory.position(cand.frame, p);
    for (int a = 0; a < 3; ++a) {
      const double allowance =
          kPrintedDigitsRounding * std::max(std::abs(double(x[a])), std::abs(double(y[a]))) +
          kFloatRounding * box_scale_cu;
      double ratio = std::abs(double(y[a]) - x[a]) / allowance;
      if (!std::isfinite(ratio)) ratio = INFINITY;  // a NaN is the worst of all
      if (ratio > worst)
        worst = ratio, particle = p, axis = a, reference_cu = x[a], candidate_cu = y[a];
    }
  }
  static constexpr double kPrintedDigitsRounding = 1e-5;  // two %g prints: 5e-6 of |x| each
  static constexpr double kFloatRounding = 1e-7;          // float32's epsilon, 6e-8, rounded up
};

// Paired frames at which the candidate's moving particles all stand exactly where they stood at
// the paired frame before while the reference's moved by more than two prints' rounding: a frame
// written twice (a readback that returned the last frame's buffer), not a simulation, which
// moves something in every step. One such frame moved no particle farther than the motion gates
// admit: demo1's frame 250 written again as 249 passed every gate (docs/checklist.md, round 7).
struct StaleFrames {
  // A paired frame is stale when no moving particle of the candidate moved since the paired
  // frame before while the reference's did, or when at least this fraction of the moving
  // particles held exactly still where the reference's moved: a frame read back mid-update (one
  // particle, the tracked one, new and the rest the frame before's) repeats all but a few.
  static constexpr double kStillFraction = 0.5;
  std::size_t count = 0, first_reference_frame = 0;
  std::size_t held_at_first = 0;  // particles held still where the reference's moved, first frame
  std::vector<float> last[2];     // the moving particles' positions at the last pair (ref, cand)
  // A candidate logged more finely than the reference has frames between the paired ones, which
  // no other gate reads: its frame just after the last pair, when it repeated that pair's frame
  // (bit for bit), and its frame just before the next pair (the moving particles' positions).
  // Either repeating its paired neighbour while the reference moved over the interval is a
  // frame written twice: logging twice as often with every other frame a copy passed every gate.
  bool after_repeated = false;
  std::vector<float> before;

  static bool Repeats(const FrameRef& cand, const std::vector<std::size_t>& moving,
                      const std::vector<float>& positions) {
    for (std::size_t k = 0; k < moving.size(); ++k) {
      const float* y = cand.trajectory.position(cand.frame, moving[k]);
      for (int a = 0; a < 3; ++a)
        if (!(y[a] == positions[3 * k + a])) return false;
    }
    return true;
  }
  // The unpaired candidate frame just after the last pair.
  void ObserveAfterPair(const FrameRef& cand, const std::vector<std::size_t>& moving) {
    after_repeated = !last[1].empty() && Repeats(cand, moving, last[1]);
  }
  // The unpaired candidate frame just before the next pair.
  void ObserveBeforePair(const FrameRef& cand, const std::vector<std::size_t>& moving) {
    before.resize(3 * moving.size());
    for (std::size_t k = 0; k < moving.size(); ++k)
      for (int a = 0; a < 3; ++a)
        before[3 * k + a] = cand.trajectory.position(cand.frame, moving[k])[a];
  }

  void Count(std::size_t reference_frame, std::size_t held) {
    if (count++ == 0) first_reference_frame = reference_frame, held_at_first = held;
  }

  void Observe(const FrameRef& ref, const FrameRef& cand, const std::vector<std::size_t>& moving,
               std::size_t reference_frame, double box_scale_cu) {
    bool reference_moved = false, candidate_moved = false;
    std::size_t held = 0;  // moving particles the reference moved and the candidate held still
    const bool first = last[0].empty();
    const bool before_repeats = !before.empty() && Repeats(cand, moving, before);
    if (first) last[0].resize(3 * moving.size()), last[1].resize(3 * moving.size());
    for (std::size_t k = 0; k < moving.size(); ++k) {
      const float* x = ref.trajectory.position(ref.frame, moving[k]);
      const float* y = cand.trajectory.position(cand.frame, moving[k]);
      bool reference_moves = false, candidate_moves = false;
      for (int a = 0; a < 3; ++a) {
        float& was_x = last[0][3 * k + a];
        float& was_y = last[1][3 * k + a];
        const double allowance = InitialState::kPrintedDigitsRounding * std::abs(double(x[a])) +
                                 InitialState::kFloatRounding * box_scale_cu;
        reference_moves |= std::abs(double(x[a]) - was_x) > allowance;
        candidate_moves |= !(y[a] == was_y);
        was_x = x[a], was_y = y[a];
      }
      reference_moved |= reference_moves, candidate_moved |= candidate_moves;
      held += reference_moves && !candidate_moves;
    }
    const bool after_repeated_last = after_repeated;
    after_repeated = false, before.clear();
    if (first) return;
    if ((reference_moved && !candidate_moved) ||
        double(held) >= kStillFraction * double(moving.size()))
      Count(reference_frame, held);
    if (reference_moved && after_repeated_last) Count(reference_frame, moving.size());
    if (reference_moved && before_repeats) Count(reference_frame, moving.size());
  }
};

}  // namespace owval::compare::internal
