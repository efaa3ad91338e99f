#include "owval/compare/parity.hpp"

#include <algorithm>
#include <string>
#include <vector>

#include "owval/base/errors.hpp"
#include "pair_reducer.hpp"
#include "parity_gates.hpp"

namespace owval::compare {
// The reduction and the gates are this file's parts (pair_reducer.hpp, parity_gates.hpp).
using namespace internal;
namespace {

double BoxScale(const Box& box) {
  const double s = std::max({box.extent(0), box.extent(1), box.extent(2)});
  return s > 0 ? s : 1.0;
}

// The gated pairs, as indices into `pairs`: every pair, or the pair of each sample frame.
std::vector<std::size_t> GatedPairs(const Pairs& pairs, const Trajectory& ref,
                                    const ParityOptions& o) {
  std::vector<std::size_t> gated;
  if (o.sample_frames.empty()) {
    for (std::size_t k = 0; k < pairs.size(); ++k) gated.push_back(k);
    return gated;
  }
  for (std::size_t f : o.sample_frames) {
    auto it = std::find_if(pairs.begin(), pairs.end(), [f](const auto& p) { return p.first == f; });
    if (f >= ref.frame_count())
      throw InputError("sample frame " + std::to_string(f) + " is past the reference's end (" +
                       std::to_string(ref.frame_count()) + " frames, counted from 0)");
    if (it == pairs.end())
      throw InputError("sample frame " + std::to_string(f) +
                       " has no candidate frame at t = " + std::to_string(ref.time_s[f]) + " s");
    gated.push_back(std::size_t(it - pairs.begin()));
  }
  return gated;
}

}  // namespace

namespace {

// The frames of both runs paired by time, and which pairs the frame gates judge.
struct PairedFrames {
  Pairs pairs;
  std::vector<std::size_t> gated;
  std::size_t misaligned = 0;
};

// What every comparison starts from: the runs checked against each other, their frames paired,
// and the report's header.
PairedFrames StartReport(FrameSource& refs, FrameSource& cands, const ParityOptions& o,
                         ParityReport* r) {
  const Trajectory& ref = refs.header();
  const Trajectory& cand = cands.header();
  if (ref.particle_count() != cand.particle_count())
    throw InputError("wrong particle count: the reference has " +
                     std::to_string(ref.particle_count()) + " particles, the candidate " +
                     std::to_string(cand.particle_count()));
  // One frame is no run to compare with: its window is an instant, and a candidate frozen after
  // its first frame passed every gate.
  if (ref.frame_count() < 2)
    throw InputError("the reference holds " + std::to_string(ref.frame_count()) +
                     " frame(s); expected at least 2, a run over time to compare with");
  o.track.Validate(ref);
  PairedFrames p;
  p.pairs = PairFramesByTime(ref, cand, &p.misaligned);
  if (p.pairs.empty()) throw InputError("the reference and candidate share no frame time");
  p.gated = GatedPairs(p.pairs, ref, o);
  r->subject = o.track.Describe();
  r->paired_frames = p.pairs.size();
  r->common_window_start_s = ref.time_s[p.pairs.front().first];
  r->common_window_end_s = ref.time_s[p.pairs.back().first];
  r->box_scale_cu = BoxScale(ref.box);
  r->reference_partial = refs.partial(), r->candidate_partial = cands.partial();
  return p;
}

}  // namespace

ParityReport CompareFrameSources(FrameSource& refs, FrameSource& cands, const ParityOptions& o) {
  const Trajectory& ref = refs.header();
  const Trajectory& cand = cands.header();
  ParityReport r;
  const PairedFrames paired = StartReport(refs, cands, o, &r);
  const Pairs& pairs = paired.pairs;
  const std::vector<std::size_t>& gated = paired.gated;
  PairReducer reducer(ref, cand, refs, pairs, gated, o, &r);
  Reduce(refs, cands, pairs, &reducer, o.quiet);
  MeasureSignals(reducer, o, &r);
  GateWindow(ref, o, &r);
  r.misaligned_pairs = paired.misaligned;
  GateSampling(ref, pairs, o, &r);
  GateSamplingOscillation(ref, pairs, o, &r);
  GateTimeBase(cand, o, &r);
  GateParticleTypes(ref, cand, &r);
  GateStaleFrames(reducer, &r);
  GateInitialState(ref, reducer, o, &r);
  GateBoundaryFixed(ref, reducer, o, &r);
  GateClosestApproach(ref, reducer, o, &r);
  GateHeldPair(ref, pairs, reducer, o, &r);
  GateLiquidPacking(reducer, o, &r);
  GateAcceleration(reducer, o, &r);
  GateAccelerationStencil(reducer, o, &r);
  GateUnpairedFrames(reducer, o, &r);
  GateFrames(ref, pairs, gated, o, &r);
  GateFramesPosition(pairs, gated, reducer, o, &r);
  GateSampledGroups(pairs, gated, reducer, o, &r);
  GateOscillation(o, &r);
  GateGroups(o, &r);
  GateWorstParticles(reducer, o, &r);
  reducer.bodies().AddGates(&r);
  return r;
}

ParityReport CompareTrajectories(const Trajectory& ref, const Trajectory& cand,
                                 const ParityOptions& o) {
  const auto refs = MemoryFrameSource(ref), cands = MemoryFrameSource(cand);
  return CompareFrameSources(*refs, *cands, o);
}

// CompareFrameSources's reduction with only what these two gates need (PairReducer::Scope). The
// checklist makes the whole report first; making it again for these two gates had been a fifth
// of its time (the closest approach's neighbour grid above all).
SampledFrameParity CompareSampledFrames(FrameSource& refs, FrameSource& cands,
                                        const ParityOptions& o) {
  ParityReport r;
  const PairedFrames paired = StartReport(refs, cands, o, &r);
  PairReducer reducer(refs.header(), cands.header(), refs, paired.pairs, paired.gated, o, &r,
                      PairReducer::Scope::kSampledFrameGates);
  Reduce(refs, cands, paired.pairs, &reducer, o.quiet);
  MeasureSignals(reducer, o, &r);
  GateFrames(refs.header(), paired.pairs, paired.gated, o, &r);
  GateSampledGroups(paired.pairs, paired.gated, reducer, o, &r);
  SampledFrameParity p{*r.gate("frames"), std::nullopt, std::move(r.failing_frames)};
  if (const Gate* groups = r.gate("frames.group_centroids")) p.group_centroids = *groups;
  return p;
}

std::vector<Gate> SampledFrameParity::gates() const {
  std::vector<Gate> both{frames};
  if (group_centroids) both.push_back(*group_centroids);
  return both;
}

}  // namespace owval::compare
