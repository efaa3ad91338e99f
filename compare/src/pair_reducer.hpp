#pragma once
// The reduction of two runs' paired frames, in time order, to what every gate of the parity
// report needs (PairReducer), and the loop that feeds it (Reduce).
#include <array>
#include <cstddef>
#include <map>
#include <optional>
#include <utility>
#include <vector>

#include "body_gates.hpp"
#include "closest_approach.hpp"
#include "frame_acceleration.hpp"
#include "frame_checks.hpp"
#include "group_drift.hpp"
#include "held_pairs.hpp"
#include "liquid_packing.hpp"
#include "owval/compare/parity.hpp"
#include "owval/trajectory/frame_source.hpp"
#include "unpaired_frames.hpp"

namespace owval::compare::internal {

using Pairs = std::vector<std::pair<std::size_t, std::size_t>>;

// Everything the gates need, reduced frame pair by frame pair in time order (one frame of each
// trajectory at a time): the tracked series, the per-particle distances, each group's drift,
// the group centroid distances at the sampled pairs, and the scene gates' measures.
class PairReducer {
 public:
  // What the reduction is for: every gate of the report, or only the gates at the sample frames
  // (GateFrames, GateSampledGroups), which need the tracked scalar at every paired frame and the
  // groups' centroids at the sample frames, nothing more.
  enum class Scope { kEveryGate, kSampledFrameGates };

  PairReducer(const Trajectory& ref, const Trajectory& cand, FrameSource& ref_frames,
              const Pairs& pairs, const std::vector<std::size_t>& gated, const ParityOptions& o,
              ParityReport* r, Scope scope = Scope::kEveryGate);

  void Observe(std::size_t k, const FrameRef& a, const FrameRef& b, double cand_time);

  // After the last pair.
  void Finish();
  // The reference's tracked scalar at one of its frames inside the common window, paired or
  // not: what the reference does between the paired frames (a candidate logged sparsely sees
  // none of it).
  void ObserveReferenceFrame(std::size_t f, const FrameRef& a) {
    resolved_time_.push_back(ref_.time_s[f]);
    resolved_series_.push_back(o_.track.ValueAt(a.trajectory, a.frame));
    if (scope_ == Scope::kEveryGate)
      for (SpeedKind& s : speeds_) s.reference.Observe(a, f, ref_.time_s[f]);
  }
  const std::vector<double>& candidate_time() const { return cand_time_; }
  const std::vector<double>& resolved_time() const { return resolved_time_; }
  const std::vector<double>& resolved_series() const { return resolved_series_; }
  // The 3-D centroid distance of group g (0 elastic, 1 liquid) at sampled pair k, of the box.
  double SampleDistance(std::size_t k, int g) const { return sample_distance_.at(k)[g]; }
  bool HasSampleGroup(int g) const { return !sample_groups_[g].empty(); }
  BodyGates& bodies() { return bodies_; }
  const std::vector<WorstParticle>& worst_particles() const { return worst_; }
  // The tracked particle's (or group centroid's) 3-D offset cand - ref (cu) at pair k.
  const std::array<double, 3>& tracked_offset_cu(std::size_t k) const {
    return tracked_offset_cu_[k];
  }
  const InitialState& initial_state() const { return initial_; }
  const InitialState& walls() const { return walls_; }
  const StaleFrames& stale_frames() const { return stale_; }
  // The candidate's unpaired frames (a candidate logged more finely than the reference), each
  // between the pairs k - 1 and k, read only when every gate is: the excursions read them all,
  // StaleFrames those beside a pair (one frame between two pairs is beside both).
  bool wants_unpaired_candidate_frames() const {
    return scope_ == Scope::kEveryGate && !moving_.empty();
  }
  void ObserveUnpairedCandidate(std::size_t k, std::size_t f, const FrameRef& b) {
    for (SpeedKind& s : speeds_) s.candidate.ObserveUnpaired(b);
    if (f == pairs_[k - 1].second + 1) stale_.ObserveAfterPair(b, moving_);
    if (f + 1 == pairs_[k].second) stale_.ObserveBeforePair(b, moving_);
  }
  const ClosestApproach& closest_approach() const { return closest_; }
  // Each run's held pairs (reference, candidate); empty when the scene has no moving particle.
  const std::optional<HeldPairs>& held_reference() const { return held_[0]; }
  const std::optional<HeldPairs>& held_candidate() const { return held_[1]; }
  double held_spacing_cu() const { return held_spacing_cu_; }
  bool has_moving_particles() const { return !moving_.empty(); }
  bool has_liquid() const { return !liquid_.empty(); }
  const PackingReduction& packing() const { return packing_; }
  const AccelerationReduction& acceleration() const { return acceleration_; }
  const std::vector<SpeedKind>& speeds() const { return speeds_; }

 private:
  void ObserveSample(std::size_t k, const FrameRef& a, const FrameRef& b);

  Scope scope_;
  const Trajectory& ref_;
  const ParityOptions& o_;
  ParityReport* r_;
  const Pairs& pairs_;
  std::vector<std::size_t> moving_;
  std::vector<bool> sampled_;
  std::vector<std::vector<std::size_t>> sample_groups_;
  std::map<std::size_t, std::array<double, 2>> sample_distance_;
  std::vector<DriftAccumulator> drift_;
  std::vector<WorstParticle> worst_;   // elastic, liquid, boundary: those the scene has
  InitialState initial_;               // at the reference's first frame, when it is paired
  std::vector<std::size_t> boundary_;  // the reference's boundary particles
  InitialState walls_;                 // theirs, at every paired frame
  StaleFrames stale_;                  // the candidate's frames written twice
  // Held pairs, of each run over the paired frames: the cap is half the reference's spacing at
  // its first paired frame (a pair held farther than that is no near-contact), the hold a tenth
  // of the paired frames, at least three.
  // Returns each run's closest pair within the cap (infinite when none, or not tracked).
  std::array<ClosestPair, 2> ObserveHeldPairs(std::size_t k, const FrameRef& a, const FrameRef& b);
  std::optional<HeldPairs> held_[2];
  double held_spacing_cu_ = 0;
  // The liquid's packing in each run, with a support of twice the reference's median spacing at
  // its first paired frame (Sibernetic's h = 2 r0, its particles placed r0 apart).
  void ObservePacking(std::size_t k, const FrameRef& a, const FrameRef& b);
  std::vector<std::size_t> liquid_;  // the reference's liquid particles
  PackingReduction packing_;
  AccelerationReduction acceleration_;  // per moving kind the reference has
  std::vector<SpeedKind> speeds_;       // the same kinds
  ClosestApproach closest_;             // of each run, over the paired frames
  // The closest-pair search's first cell width, of the box's largest extent (it widens itself).
  static constexpr double kClosestApproachCell = 0.01;
  std::vector<double> cand_time_;
  std::vector<double> resolved_time_, resolved_series_;   // every reference frame in the window
  std::vector<std::size_t> tracked_members_;              // the tracked particle or group
  std::vector<std::array<double, 3>> tracked_offset_cu_;  // per pair
  double l2_sum_ = 0;
  BodyGates bodies_;
};

// Reads the paired frames of both sources in time order and reduces them.
void Reduce(FrameSource& refs, FrameSource& cands, const Pairs& pairs, PairReducer* reducer,
            bool quiet);

}  // namespace owval::compare::internal
