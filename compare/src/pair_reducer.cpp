#include "pair_reducer.hpp"

#include "owval/base/progress.hpp"

namespace owval::compare::internal {

PairReducer::PairReducer(const Trajectory& ref, const Trajectory& cand, FrameSource& ref_frames,
                         const Pairs& pairs, const std::vector<std::size_t>& gated,
                         const ParityOptions& o, ParityReport* r, Scope scope)
    : scope_(scope),
      ref_(ref),
      o_(o),
      r_(r),
      pairs_(pairs),
      moving_(MovingParticles(ref)),
      sampled_(pairs.size(), false),
      bodies_(ref, cand, ref_frames, o.gates) {
  // Each kind's particles in file order, found once: every reduction below reads these lists.
  std::vector<std::size_t> elastic, boundary;
  for (std::size_t p = 0; p < ref.particle_count(); ++p) {
    const ParticleKind kind = KindOf(ref.type[p]);
    if (kind == ParticleKind::kElastic)
      elastic.push_back(p);
    else if (kind == ParticleKind::kLiquid)
      liquid_.push_back(p);
    else
      boundary.push_back(p);
  }
  for (const auto& [name, members] :
       {std::pair<const char*, const std::vector<std::size_t>&>{"elastic", elastic},
        {"liquid", liquid_}}) {
    sample_groups_.push_back(members);
    if (members.empty()) continue;
    acceleration_.kinds.emplace_back(name, members);
    speeds_.emplace_back(name, members);
    DriftAccumulator g;
    g.d.group = name;
    g.members = members;
    drift_.push_back(std::move(g));
    worst_.push_back({name, members});
  }
  if (!boundary.empty()) worst_.push_back({"boundary", boundary});
  boundary_ = std::move(boundary);
  if (!o.sample_frames.empty())
    for (std::size_t k : gated) sampled_[k] = true;
  tracked_members_ = o.track.group.empty() ? std::vector<std::size_t>{o.track.particle}
                                           : GroupIndices(ref, o.track.group);
}

void PairReducer::Observe(std::size_t k, const FrameRef& a, const FrameRef& b, double cand_time) {
  ObserveReferenceFrame(pairs_[k].first, a);
  r_->paired_time_s.push_back(ref_.time_s[pairs_[k].first]);
  cand_time_.push_back(cand_time);
  r_->reference_series.push_back(o_.track.ValueAt(a.trajectory, a.frame));
  r_->candidate_series.push_back(o_.track.ValueAt(b.trajectory, b.frame));
  if (scope_ == Scope::kSampledFrameGates) {
    if (sampled_[k]) ObserveSample(k, a, b);
    return;
  }
  for (SpeedKind& s : speeds_) s.candidate.ObservePaired(b, pairs_[k].second, cand_time);
  const auto x = Centroid(a.trajectory, a.frame, tracked_members_),
             y = Centroid(b.trajectory, b.frame, tracked_members_);
  tracked_offset_cu_.push_back({y[0] - x[0], y[1] - x[1], y[2] - x[2]});
  const double l2 = MeanParticleDistance(a, b, moving_);
  l2_sum_ += l2;
  if (k == 0) r_->l2_initial_cu = l2;
  r_->l2_final_cu = l2;
  for (DriftAccumulator& g : drift_) g.Observe(a, b, ref_.box);
  for (WorstParticle& w : worst_) w.Observe(a, b, pairs_[k].first);
  if (k == 0 && pairs_[k].first == 0) initial_.Observe(a, b, r_->box_scale_cu);
  walls_.Observe(a, b, r_->box_scale_cu, boundary_, pairs_[k].first);
  if (!moving_.empty()) stale_.Observe(a, b, moving_, pairs_[k].first, r_->box_scale_cu);
  const std::array<ClosestPair, 2> known = ObserveHeldPairs(k, a, b);
  if (!moving_.empty())
    closest_.Observe(a, b, moving_, kClosestApproachCell * r_->box_scale_cu, pairs_[k].first,
                     known);
  ObservePacking(k, a, b);
  acceleration_.Observe(a, b, ref_.time_s[pairs_[k].first], pairs_[k].first);
  if (sampled_[k]) ObserveSample(k, a, b);
  bodies_.Observe(a, b, r_->box_scale_cu);
}

void PairReducer::Finish() {
  if (scope_ == Scope::kSampledFrameGates) return;
  r_->l2_mean_cu = l2_sum_ / double(pairs_.size());
  for (DriftAccumulator& g : drift_) {
    g.FinishPose();
    r_->drift.push_back(g.d);
  }
}

void PairReducer::ObserveSample(std::size_t k, const FrameRef& a, const FrameRef& b) {
  std::array<double, 2> d{0, 0};
  for (int g = 0; g < 2; ++g) {
    if (sample_groups_[g].empty()) continue;
    const auto x = Centroid(a.trajectory, a.frame, sample_groups_[g]),
               y = Centroid(b.trajectory, b.frame, sample_groups_[g]);
    d[g] = std::hypot(x[0] - y[0], x[1] - y[1], x[2] - y[2]) / r_->box_scale_cu;
  }
  sample_distance_[k] = d;
}

std::array<ClosestPair, 2> PairReducer::ObserveHeldPairs(std::size_t k, const FrameRef& a,
                                                         const FrameRef& b) {
  constexpr ClosestPair kNone{std::numeric_limits<double>::infinity()};
  if (moving_.empty()) return {kNone, kNone};
  if (k == 0) {
    held_spacing_cu_ = MedianNearestSpacing(a, moving_, kClosestApproachCell * r_->box_scale_cu);
    if (!(held_spacing_cu_ > 0)) return {kNone, kNone};
    const std::size_t hold = std::max<std::size_t>(3, pairs_.size() / 10);
    for (auto& h : held_) h.emplace(held_spacing_cu_ / 2, hold);
  }
  if (!held_[0]) return {kNone, kNone};
  return {held_[0]->Observe(a, moving_, k), held_[1]->Observe(b, moving_, k)};
}

void PairReducer::ObservePacking(std::size_t k, const FrameRef& a, const FrameRef& b) {
  if (liquid_.empty()) return;
  if (k == 0) packing_.support_cu = 2 * held_spacing_cu_;
  if (!(packing_.support_cu > 0)) return;
  const PackingSummary x = MeasurePacking(a, liquid_, packing_.support_cu);
  const PackingSummary y = MeasurePacking(b, liquid_, packing_.support_cu);
  packing_.Observe(x, y, pairs_[k].first);
}

// Reads the paired frames of both sources in time order and reduces them.
void Reduce(FrameSource& refs, FrameSource& cands, const Pairs& pairs, PairReducer* reducer,
            bool quiet) {
  Progress progress("compare", pairs.size(), quiet || pairs.size() < 1000);
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    for (std::size_t f = k ? pairs[k - 1].first + 1 : pairs[k].first; f < pairs[k].first; ++f)
      reducer->ObserveReferenceFrame(f, refs.Frame(f));
    // A candidate logged more finely: its frames between the pairs.
    if (k && reducer->wants_unpaired_candidate_frames())
      for (std::size_t f = pairs[k - 1].second + 1; f < pairs[k].second; ++f)
        reducer->ObserveUnpairedCandidate(k, f, cands.Frame(f));
    const FrameRef a = refs.Frame(pairs[k].first);
    const FrameRef b = cands.Frame(pairs[k].second);
    reducer->Observe(k, a, b, cands.header().time_s[pairs[k].second]);
    if ((k & 63) == 63) progress.Update(k + 1);
  }
  reducer->Finish();
}

}  // namespace owval::compare::internal
