#include "parity_gates.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "owval/base/format.hpp"

namespace owval::compare::internal {
namespace {

std::optional<double> RelativeGap(const std::optional<double>& ref,
                                  const std::optional<double>& cand) {
  if (!ref || !cand || *ref == 0) return std::nullopt;
  return (*cand - *ref) / *ref;
}

std::string FailingList(const std::vector<std::size_t>& frames) {
  std::ostringstream s;
  for (std::size_t i = 0; i < frames.size() && i < 20; ++i) s << (i ? ", " : "") << frames[i];
  if (frames.size() > 20) s << ", ... (" << frames.size() << " in all)";
  return s.str();
}

}  // namespace

void GateFrames(const Trajectory& ref, const Pairs& pairs, const std::vector<std::size_t>& gated,
                const ParityOptions& o, ParityReport* r) {
  Gate g =
      MakeGate("frames", "worst |cand - ref| / scale of " + r->subject + " over the gated frames",
               0, o.gates.frame, r->scale_given ? "of the given scale" : "of the reference range");
  for (std::size_t k : gated) {
    const auto [fr, fc] = pairs[k];
    FrameParity fp{fr, fc, ref.time_s[fr], r->reference_series[k], r->candidate_series[k]};
    fp.relative_difference = std::abs(fp.candidate_value - fp.reference_value) / r->scale;
    fp.pass = std::isfinite(fp.candidate_value) && fp.relative_difference < o.gates.frame.value;
    if (!fp.pass) r->failing_frames.push_back(fr);
    g.value = std::isfinite(fp.relative_difference) ? std::max(g.value, fp.relative_difference)
                                                    : INFINITY;
    r->frames.push_back(fp);
  }
  Decide(&g);
  char scale[128];  // the longer of the two lines below with any %.4g
  std::snprintf(scale, sizeof scale, "scale %.4g cu", r->scale);
  g.detail = std::to_string(r->frames.size() - r->failing_frames.size()) + "/" +
             std::to_string(r->frames.size()) + " frames within, " + scale;
  if (r->scale_given) {
    std::snprintf(scale, sizeof scale,
                  " given by the caller (--scale), not the reference range "
                  "(%.4g cu)",
                  r->reference_range);
    g.detail += scale;
  }
  if (!r->failing_frames.empty()) g.detail += "; failing frames " + FailingList(r->failing_frames);
  r->gates.push_back(g);
}

// The frames gate in 3-D: the tracked particle's (or group centroid's) whole position, not its
// tracked coordinate alone, against the same scale and threshold (DD001's 5% of the reference
// scale). one_sprig tracks particle 0 y, a vertical oscillator: with gravity tilted 0.58 degrees
// (gravity_x 0.1) it swung 0.32 cu sideways, 9.6% of its 3.39 cu range, where the reference does
// not move at all, and every gate passed (frames 0.1%; elastic.worst_particle 1% of the box).
void GateFramesPosition(const Pairs& pairs, const std::vector<std::size_t>& gated,
                        const PairReducer& reduced, const ParityOptions& o, ParityReport* r) {
  Gate g = MakeGate(
      "frames.position",
      "worst 3-D distance / scale of the tracked " +
          std::string(o.track.group.empty() ? "particle" : "centroid") + " over the gated frames",
      0, o.gates.frame, r->scale_given ? "of the given scale" : "of the reference range");
  std::size_t worst = gated.empty() ? 0 : gated.front();
  for (std::size_t k : gated) {
    const auto& d = reduced.tracked_offset_cu(k);
    const double distance = std::hypot(d[0], d[1], d[2]) / r->scale;
    if (!(distance <= g.value)) g.value = std::isfinite(distance) ? distance : INFINITY, worst = k;
  }
  if (!gated.empty()) {
    const auto& d = reduced.tracked_offset_cu(worst);
    char detail[160];
    std::snprintf(detail, sizeof detail,
                  "worst at reference frame %zu: offset (x, y, z) = (%+.3g, %+.3g, %+.3g) cu",
                  pairs[worst].first, d[0], d[1], d[2]);
    g.detail = detail;
  }
  Decide(&g);
  r->gates.push_back(g);
}

// The common window against the reference's whole duration (n/a for a one-frame reference).
void GateWindow(const Trajectory& ref, const ParityOptions& o, ParityReport* r) {
  const double start = ref.time_s.front(), end = ref.time_s.back(), duration = end - start;
  const double outside = (r->common_window_start_s - start) + (end - r->common_window_end_s);
  Gate g = MakeGate("window", "part of the reference's duration outside the common window",
                    duration > 0 ? outside / duration : 0, o.gates.window,
                    "of the reference's duration");
  char detail[160];
  std::snprintf(detail, sizeof detail,
                "common window %.6g s to %.6g s of the reference's %.6g s to %.6g s",
                r->common_window_start_s, r->common_window_end_s, start, end);
  g.detail = detail;
  if (duration > 0) {
    Decide(&g);
  } else {
    g.detail += " (one frame: nothing to cover)";
  }
  r->gates.push_back(g);
}

// The longest stretch between two paired frames that skips reference frames, of the reference's
// duration: every other gate looks only at paired frames, so a candidate logged at two well-chosen
// instants (a wrong spring that happens to be back in phase at the end) would agree with anything
// in between. A candidate on a coarser log step than the reference passes while its frames stay
// close together.
void GateSampling(const Trajectory& ref, const Pairs& pairs, const ParityOptions& o,
                  ParityReport* r) {
  const double duration = ref.time_s.back() - ref.time_s.front();
  double longest = 0;
  std::size_t after = 0;
  for (std::size_t k = 0; k + 1 < pairs.size(); ++k) {
    const double gap = ref.time_s[pairs[k + 1].first] - ref.time_s[pairs[k].first];
    if (pairs[k + 1].first > pairs[k].first + 1 && gap > longest) longest = gap, after = k;
  }
  Gate g = MakeGate("sampling",
                    "longest time between paired frames that skips reference frames, of the "
                    "reference's duration",
                    duration > 0 ? longest / duration : 0, o.gates.sampling,
                    "of the reference's duration");
  char detail[200];
  std::snprintf(detail, sizeof detail, "%zu of the reference's %zu frames paired", pairs.size(),
                ref.frame_count());
  g.detail = detail;
  if (r->misaligned_pairs > 0)
    g.detail += " (" + std::to_string(r->misaligned_pairs) +
                " more within half a frame but at another time left out: the frame times do "
                "not line up)";
  if (longest > 0) {
    std::snprintf(detail, sizeof detail, "; longest gap %.6g s to %.6g s",
                  ref.time_s[pairs[after].first], ref.time_s[pairs[after + 1].first]);
    g.detail += detail;
  }
  if (duration > 0) Decide(&g);
  r->gates.push_back(g);
}

namespace {
// min_crossings decides whether the oscillation gates apply at all (a flag's 1000 turns them n/a
// on any spring), so an override of it is an override of those gates: their source says so, as a
// changed threshold's does, and their detail names it.
void LabelMinCrossings(const Threshold& min_crossings, Gate* g) {
  if (min_crossings.source == ThresholdSource::kDefault) return;
  g->threshold.source = std::max(g->threshold.source, min_crossings.source);  // flag > manifest
  g->detail += "; min_crossings " + FormatNumber(min_crossings.value) + " from " +
               SourceName(min_crossings.source) + " (default " +
               FormatNumber(ParityGates{}.min_crossings.value) + ")";
}
}  // namespace

// The candidate's frame times evenly spaced: every interval within a fraction of the mean one.
// Every writer logs every log_step steps (WCSPH lands its adaptive steps on the frame times), but
// an HDF5 /time column can say anything: a stiffer spring's frames, each relabelled with the
// reference frame time nearest its stretched time, met the reference's frames densely and in
// phase. n/a below three frames.
void GateTimeBase(const Trajectory& cand, const ParityOptions& o, ParityReport* r) {
  const std::vector<double>& t = cand.time_s;
  const double mean = t.size() > 2 ? (t.back() - t.front()) / double(t.size() - 1) : 0;
  double worst = 0;
  std::size_t at = 0;
  for (std::size_t j = 1; j < t.size() && mean > 0; ++j) {
    const double off = std::abs(t[j] - t[j - 1] - mean) / mean;
    if (!(off <= worst)) worst = off, at = j;
  }
  Gate g = MakeGate("time_base",
                    "largest departure of a candidate frame interval from its mean interval", worst,
                    o.gates.time_base, "of the mean interval");
  char detail[160];
  std::snprintf(detail, sizeof detail,
                "mean interval %.6g s; worst between candidate frames %zu and %zu", mean,
                at ? at - 1 : 0, at);
  g.detail = mean > 0 ? detail : "fewer than three frames";
  if (mean > 0) Decide(&g);
  r->gates.push_back(g);
}

// The longest time between two paired frames that skips reference frames, against the
// reference's own period when it oscillates over its frames (min_crossings upward crossings): a
// gap of half a period or more cannot resolve the oscillation (Nyquist), and aliased samples of
// a wrong oscillation can agree with aliased samples of the right one. n/a when the reference
// does not oscillate or every reference frame is paired.
void GateSamplingOscillation(const Trajectory& ref, const Pairs& pairs, const ParityOptions& o,
                             ParityReport* r) {
  double longest = 0;
  for (std::size_t k = 0; k + 1 < pairs.size(); ++k)
    if (pairs[k + 1].first > pairs[k].first + 1)
      longest = std::max(longest, ref.time_s[pairs[k + 1].first] - ref.time_s[pairs[k].first]);
  const bool oscillates =
      r->reference_crossings_all_frames >= std::size_t(o.gates.min_crossings.value) &&
      r->reference_period_all_frames_s && *r->reference_period_all_frames_s > 0;
  Gate g = MakeGate("sampling.oscillation",
                    "longest time between paired frames that skips reference frames, of the "
                    "reference's own period",
                    oscillates ? longest / *r->reference_period_all_frames_s : NAN,
                    o.gates.sampling_period, "of the reference's period");
  if (!oscillates) {
    g.detail = "the reference does not oscillate over its own frames (" +
               std::to_string(r->reference_crossings_all_frames) + " upward mean crossings)";
  } else {
    char detail[160];
    std::snprintf(detail, sizeof detail, "longest gap %.4g s, reference period %.6g s", longest,
                  *r->reference_period_all_frames_s);
    g.detail = detail;
    Decide(&g);
  }
  LabelMinCrossings(o.gates.min_crossings, &g);
  r->gates.push_back(g);
}

void GateOscillation(const ParityOptions& o, ParityReport* r) {
  const std::size_t need = static_cast<std::size_t>(o.gates.min_crossings.value);
  const std::size_t nr = r->reference_metrics.upward_crossings,
                    nc = r->candidate_metrics.upward_crossings;
  const bool applies = nr >= need && nc >= need && r->period_gap && r->half_amplitude_gap;
  // The reference oscillates over its own frames in the common window: a candidate whose
  // paired frames show no oscillation (it does not oscillate, or it was logged too sparsely to
  // see it) fails these gates instead of escaping them as n/a.
  const std::size_t all = r->reference_crossings_all_frames;
  const bool unseen = !applies && all >= need;
  const std::string why_unseen =
      "the reference has " + std::to_string(all) +
      " upward mean crossings over its own frames in the common window, but the paired frames " +
      "show " + std::to_string(nr) + " (reference) and " + std::to_string(nc) +
      " (candidate): the candidate does not oscillate, or its frames do not resolve it";
  const std::string why_not = "reference has " + std::to_string(nr) +
                              " upward mean crossings, candidate " + std::to_string(nc) +
                              "; oscillation gates need >= " + std::to_string(need) + " in both";
  auto add = [&](const char* name, const char* what, const std::optional<double>& gap,
                 const Threshold& t) {
    Gate g = MakeGate(name, what, applies ? std::abs(*gap) : NAN, t, "relative");
    if (applies) {
      Decide(&g);
      char b[64];
      std::snprintf(b, sizeof b, "gap %+.3f%%", *gap * 100);
      g.detail = b;
    } else if (unseen) {
      g.status = GateStatus::kFail;
      g.detail = why_unseen;
    } else {
      g.status = GateStatus::kNotApplicable;
      g.detail = why_not;
    }
    LabelMinCrossings(o.gates.min_crossings, &g);
    r->gates.push_back(g);
  };
  add("period", "|zero-crossing period gap| of the tracked scalar", r->period_gap,
      o.gates.period_gap);
  add("half_amplitude", "|half-amplitude gap| of the tracked scalar", r->half_amplitude_gap,
      o.gates.amplitude_gap);
}

void GateGroups(const ParityOptions& o, ParityReport* r) {
  const std::string box = "of the box (" + std::to_string(r->box_scale_cu).substr(0, 6) + " cu)";
  for (const GroupDrift& d : r->drift) {
    Gate c = MakeGate(d.group + ".centroid_distance",
                      "max over time of the 3-D " + d.group + " centroid distance",
                      d.max_centroid_distance_cu / r->box_scale_cu, o.gates.centroid_distance, box);
    Gate e = MakeGate(
        d.group + ".extent",
        "max over time and axes of the " + d.group + " bounding-box extent difference",
        d.max_extent_difference_fraction, o.gates.extent, "of the box extent on that axis");
    Gate f = MakeGate(d.group + ".final_distance",
                      "3-D " + d.group + " centroid distance at the last frame",
                      d.final_centroid_distance_cu / r->box_scale_cu, o.gates.final_distance, box);
    char offset[128];
    std::snprintf(offset, sizeof offset, "last-frame offset (x, y, z) = (%+.3g, %+.3g, %+.3g) cu",
                  d.final_offset_cu[0], d.final_offset_cu[1], d.final_offset_cu[2]);
    f.detail = offset;
    if (d.group == "elastic" && d.has_pose) {
      char turned[200];
      std::snprintf(turned, sizeof turned,
                    "last frame: turned %.1f deg (reference) and %.1f deg (candidate) since the "
                    "first; extents in each run's own axes cand/ref (x, y, z) = (%.3f, %.3f, %.3f)",
                    d.final_rotation_deg[0], d.final_rotation_deg[1], d.final_body_extent_ratio[0],
                    d.final_body_extent_ratio[1], d.final_body_extent_ratio[2]);
      e.detail = turned;
    }
    for (Gate* g : {&c, &e, &f}) {
      Decide(g);
      r->gates.push_back(*g);
    }
  }
  const std::pair<const char*, double> l2[] = {
      {"initial", r->l2_initial_cu}, {"mean", r->l2_mean_cu}, {"final", r->l2_final_cu}};
  for (const auto& [when, value] : l2) {
    Gate g = MakeGate(std::string("particle_distance.") + when,
                      std::string("mean per-particle distance of moving particles, ") + when,
                      value / r->box_scale_cu, o.gates.particle_distance, box);
    Decide(&g);
    r->gates.push_back(g);
  }
}

// Per kind of particle, the worst single particle over the paired frames, of the box: the mean
// gates above let one particle go anywhere. One threshold for every kind: liquid too, although
// its particles are chaotic, since on the scenes measured (docs/checklist.md) every port that
// differs at all fails the liquid centroid and particle_distance gates already, by far more.
void GateWorstParticles(const PairReducer& reduced, const ParityOptions& o, ParityReport* r) {
  const std::string box = "of the box (" + FormatNumber(r->box_scale_cu, 5) + " cu)";
  for (const WorstParticle& w : reduced.worst_particles()) {
    Gate g = MakeGate(std::string(w.group) + ".worst_particle",
                      std::string("max over ") + w.group +
                          " particles and paired frames of the particle's 3-D distance",
                      w.distance_cu / r->box_scale_cu, o.gates.worst_particle, box);
    char detail[160];
    std::snprintf(detail, sizeof detail, "particle %zu at reference frame %zu: %.4g cu", w.particle,
                  w.reference_frame, w.distance_cu);
    g.detail = detail;
    Decide(&g);
    r->gates.push_back(g);
  }
}

// The candidate at the reference's first frame against it, particle for particle (InitialState).
// A candidate with no frame at the reference's first time cannot show where it started: it fails.
void GateInitialState(const Trajectory& ref, const PairReducer& reduced, const ParityOptions& o,
                      ParityReport* r) {
  const InitialState& s = reduced.initial_state();
  Gate g =
      MakeGate("initial_state",
               "worst coordinate's |cand - ref| at the reference's first frame, in units of "
               "the rounding of two 6-significant-digit prints",
               s.observed ? s.worst : INFINITY, o.gates.initial_state, "of the printed precision");
  char detail[240];
  if (!s.observed) {
    std::snprintf(detail, sizeof detail,
                  "the candidate has no frame at the reference's first time (%.6g s): where it "
                  "started cannot be checked",
                  ref.time_s.front());
  } else if (s.worst == 0) {
    std::snprintf(detail, sizeof detail, "every coordinate equal at %.6g s", ref.time_s.front());
  } else {
    std::snprintf(detail, sizeof detail,
                  "particle %zu (%s) %c at %.6g s: candidate %.7g cu, reference %.7g cu",
                  s.particle, KindName(KindOf(ref.type[s.particle])), "xyz"[s.axis],
                  ref.time_s.front(), s.candidate_cu, s.reference_cu);
  }
  g.detail = detail;
  Decide(&g);
  r->gates.push_back(g);
}

// The candidate's walls against the reference's at every paired frame, to the printed precision
// (InitialState's measure and threshold): Sibernetic never integrates a boundary particle
// (sphFluid.cl's integration skips type 3), nor does any owval backend, so an honest run's walls
// are where the reference's are in every frame. boundary.worst_particle's 5% of the box let
// every wall move 1 cu from frame 1 on (one_sprig's spring anchor with them) while the moving
// particles stayed the reference's (docs/checklist.md, round 7). n/a without boundary particles.
void GateBoundaryFixed(const Trajectory& ref, const PairReducer& reduced, const ParityOptions& o,
                       ParityReport* r) {
  const InitialState& s = reduced.walls();
  Gate g = MakeGate("boundary.fixed",
                    "worst boundary coordinate's |cand - ref| over the paired frames, in units of "
                    "the rounding of two 6-significant-digit prints",
                    s.observed ? s.worst : NAN, o.gates.initial_state, "of the printed precision");
  if (!s.observed) {
    g.detail = "the scene has no boundary particles";
    r->gates.push_back(g);
    return;
  }
  char detail[240];
  if (s.worst == 0) {
    std::snprintf(detail, sizeof detail, "every boundary coordinate equal at every paired frame");
  } else {
    std::snprintf(detail, sizeof detail,
                  "particle %zu %c at reference frame %zu (%.6g s): candidate %.7g cu, reference "
                  "%.7g cu",
                  s.particle, "xyz"[s.axis], s.reference_frame, ref.time_s[s.reference_frame],
                  s.candidate_cu, s.reference_cu);
  }
  g.detail = detail;
  Decide(&g);
  r->gates.push_back(g);
}

// The candidate's paired frames that repeat the one before while the reference moves
// (StaleFrames): none may, as no particle type may differ. n/a without moving particles. The
// detail says what was seen, not why: XPBD's free_fall particle resting exactly on the floor
// (its contact projection lands on the same float each step) while PCISPH's bounces is the
// same observation as a frame written twice.
void GateStaleFrames(const PairReducer& reduced, ParityReport* r) {
  if (!reduced.has_moving_particles()) return;
  const StaleFrames& s = reduced.stale_frames();
  Gate g = MakeGate("stale_frames",
                    "paired frames at which no moving particle of the candidate moved since the "
                    "paired frame before while the reference's moved, or half of them or more "
                    "held exactly still where the reference's moved; and unpaired candidate "
                    "frames repeating the paired frame beside them while the reference moved",
                    double(s.count), Threshold{1}, "frames");
  g.detail = s.count == 0 ? "none"
                          : std::to_string(s.count) + " (the first at reference frame " +
                                std::to_string(s.first_reference_frame) + ", " +
                                std::to_string(s.held_at_first) +
                                " particles held still): a frame written twice or read back "
                                "mid-update, or moving particles held exactly still where the "
                                "reference's move";
  Decide(&g);
  r->gates.push_back(g);
}

// The candidate's particle type codes against the reference's (Sibernetic's position.w: kind and
// sub-type, fixed by the configuration). Every gate reads the kinds from the reference's types,
// so a candidate that wrote liquid as elastic (or dropped the sub-types the worm's midline bins by)
// passed with its positions right. Equal to the printed precision (1e-5 relative: two 6-digit
// prints), since a text file prints them with 6 significant digits and HDF5 keeps the float.
void GateParticleTypes(const Trajectory& ref, const Trajectory& cand, ParityReport* r) {
  std::size_t differing = 0, first = 0;
  for (std::size_t p = 0; p < ref.particle_count(); ++p) {
    const double a = ref.type[p], b = cand.type[p];
    if (std::abs(a - b) <= 1e-5 * std::max(std::abs(a), std::abs(b))) continue;
    if (differing++ == 0) first = p;
  }
  Gate g = MakeGate("particle_types", "particles whose type code differs from the reference's",
                    double(differing), Threshold{1}, "particles");
  char detail[200];
  if (differing == 0) {
    std::snprintf(detail, sizeof detail, "all %zu equal", ref.particle_count());
  } else {
    std::snprintf(detail, sizeof detail,
                  "%zu of %zu differ; first particle %zu: candidate %.6g, reference %.6g",
                  differing, ref.particle_count(), first, double(cand.type[first]),
                  double(ref.type[first]));
  }
  g.detail = detail;
  Decide(&g);
  r->gates.push_back(g);
}

// The candidate's closest approach of two particles against the reference's (ClosestApproach):
// the value is reference / candidate, so a candidate whose particles come k times closer than the
// reference's ever do measures k, and two coincident particles infinity.
void GateClosestApproach(const Trajectory& ref, const PairReducer& reduced, const ParityOptions& o,
                         ParityReport* r) {
  if (!reduced.has_moving_particles()) return;
  const ClosestApproach& c = reduced.closest_approach();
  const double reference = c.reference.distance_cu, candidate = c.candidate.distance_cu;
  // No pair in the reference (one moving particle alone), or coincident particles in it: the
  // candidate cannot come closer than that.
  const double value = !(std::isfinite(reference) && reference > 0) ? 0
                       : candidate > 0                              ? reference / candidate
                                                                    : INFINITY;
  Gate g = MakeGate("closest_approach",
                    "the reference's closest approach of two particles (one moving) over the "
                    "paired frames / the candidate's",
                    value, o.gates.closest_approach, "times closer than the reference");
  char detail[320];
  std::snprintf(detail, sizeof detail,
                "candidate %.4g cu (particles %zu %s and %zu %s, reference frame %zu); reference "
                "%.4g cu (particles %zu and %zu, frame %zu)",
                candidate, c.candidate.first, KindName(KindOf(ref.type[c.candidate.first])),
                c.candidate.second, KindName(KindOf(ref.type[c.candidate.second])),
                c.candidate_reference_frame, reference, c.reference.first, c.reference.second,
                c.reference_frame);
  g.detail = detail;
  Decide(&g);
  r->gates.push_back(g);
}

namespace {
// The candidate's held pairs against the reference's (HeldPairs), kind of pair by kind: the
// value is the reference's held distance over the candidate's, worst kind, so a candidate that
// holds a liquid pair k times closer than the reference ever holds one for a tenth of the run
// measures k. A kind the reference never holds within the cap counts as held at the cap.
struct HeldWorst {
  double ratio = 0;
  int kind = -1;
};
HeldWorst WorstHeldKind(const HeldPairs& ref, const HeldPairs& cand) {
  HeldWorst worst;
  for (int c = 0; c < kPairKinds; ++c) {
    const int jc = cand.held()[c].level, jr = std::max(ref.held()[c].level, 0);
    if (jc < 0) continue;
    const double ratio = std::exp2(double(jc - jr) / HeldPairs::kLevelsPerOctave);
    if (ratio > worst.ratio) worst = {ratio, c};
  }
  return worst;
}

std::string HeldDetail(const Trajectory& ref, const Pairs& pairs, const HeldPairs& h, int kind,
                       const char* who) {
  const HeldPairs::Held& held = h.held()[kind];
  char detail[240];
  if (held.level < 0) {
    std::snprintf(detail, sizeof detail, "%s: none within the cap", who);
    return detail;
  }
  const std::size_t start = held.end_pair + 1 - h.hold_frames();
  std::snprintf(detail, sizeof detail,
                "%s within %.4g cu (particles %zu %s and %zu %s, reference frames %zu to %zu)", who,
                h.LevelDistanceCu(held.level), held.first, KindName(KindOf(ref.type[held.first])),
                held.second, KindName(KindOf(ref.type[held.second])), pairs[start].first,
                pairs[held.end_pair].first);
  return detail;
}
}  // namespace

void GateHeldPair(const Trajectory& ref, const Pairs& pairs, const PairReducer& reduced,
                  const ParityOptions& o, ParityReport* r) {
  if (!reduced.has_moving_particles()) return;
  const auto& href = reduced.held_reference();
  const auto& hcand = reduced.held_candidate();
  Gate g = MakeGate("held_pair",
                    "per kind of pair, the distance within which the reference holds a pair for a "
                    "tenth of the paired frames / the candidate's, worst kind",
                    NAN, o.gates.held_pair, "times closer than the reference holds");
  if (!href || pairs.size() < href->hold_frames()) {
    g.detail = "fewer paired frames than a hold (" + std::to_string(pairs.size()) +
               "), or no particle has a neighbour";
    r->gates.push_back(g);
    return;
  }
  const HeldWorst worst = WorstHeldKind(*href, *hcand);
  g.value = worst.ratio;
  char scope[200];
  std::snprintf(scope, sizeof scope,
                "; held = %zu consecutive paired frames, cap %.4g cu (half the reference's median "
                "spacing, %.4g cu)",
                href->hold_frames(), href->cap_cu(), reduced.held_spacing_cu());
  if (worst.kind < 0) {
    g.detail = std::string("the candidate holds no pair within the cap") + scope;
  } else {
    g.detail = std::string(PairKindName(worst.kind)) + ": " +
               HeldDetail(ref, pairs, *hcand, worst.kind, "candidate") + "; " +
               HeldDetail(ref, pairs, *href, worst.kind, "reference") + scope;
  }
  Decide(&g);
  r->gates.push_back(g);
}

// The candidate's liquid packing against the reference's (PackingReduction): the value is
// |mean_cand / mean_ref - 1| of the liquid's per-frame kernel-sum summaries over the paired
// frames, the larger of the median's and the upper quartile's.
void GateLiquidPacking(const PairReducer& reduced, const ParityOptions& o, ParityReport* r) {
  Gate g = MakeGate("liquid_packing",
                    "|candidate / reference - 1| of the liquid's kernel sum (Wpoly6, every "
                    "particle a neighbour), its median and upper quartile over the liquid, each "
                    "averaged over the paired frames; the larger",
                    NAN, o.gates.liquid_packing, "relative");
  const PackingReduction& p = reduced.packing();
  if (!reduced.has_liquid() || p.frames == 0) {
    g.detail = reduced.has_liquid() ? "no particle has a neighbour" : "the scene has no liquid";
    r->gates.push_back(g);
    return;
  }
  const double n = double(p.frames);
  const double median_gap = p.median_sum[1] / p.median_sum[0] - 1;
  const double quartile_gap = p.upper_quartile_sum[1] / p.upper_quartile_sum[0] - 1;
  g.value = std::max(std::abs(median_gap), std::abs(quartile_gap));
  if (std::isnan(median_gap) || std::isnan(quartile_gap)) g.value = INFINITY;
  char detail[480];
  std::snprintf(detail, sizeof detail,
                "mean over %zu paired frames of the liquid's median kernel sum (of one particle "
                "alone): candidate %.5g, reference %.5g (%+.2f%%); upper quartile: candidate "
                "%.5g, reference %.5g (%+.2f%%); the frame differing most: reference frame %zu, "
                "upper quartile candidate %.5g, reference %.5g; support %.4g cu",
                p.frames, p.median_sum[1] / n, p.median_sum[0] / n, 100 * median_gap,
                p.upper_quartile_sum[1] / n, p.upper_quartile_sum[0] / n, 100 * quartile_gap,
                p.worst_frame, p.worst[1].upper_quartile, p.worst[0].upper_quartile, p.support_cu);
  g.detail = detail;
  Decide(&g);
  r->gates.push_back(g);
}

namespace {
// An acceleration gate over the kinds that completed a stencil: `measure(kind)` gives the kind's
// value and its detail, and the gate's value is the worst kind's (a NaN value counts as
// infinite). Not applicable when no kind completed a stencil, saying why.
template <typename Measure>
void PushAccelerationGate(Gate g, const PairReducer& reduced, ParityReport* r,
                          const Measure& measure) {
  std::string details;
  for (const AccelerationReduction::Kind& k : reduced.acceleration().kinds) {
    if (k.stencils == 0) continue;
    const auto [value, detail] = measure(k);
    details += (details.empty() ? "" : "; ") + detail;
    const double judged = std::isnan(value) ? INFINITY : value;
    if (std::isnan(g.value) || judged > g.value) g.value = judged;
  }
  if (std::isnan(g.value)) {
    g.detail = reduced.has_moving_particles() ? "no three paired frames evenly spaced in time"
                                              : "the scene has no moving particles";
  } else {
    g.detail = details;
    Decide(&g);
  }
  r->gates.push_back(g);
}
}  // namespace

// The candidate's accelerations between frames against the reference's (AccelerationReduction):
// per kind, the relative gaps of the mean median and of the mean upper quartile; the value is the
// worst kind's larger gap. A reference whose particles barely move is judged against the printed
// precision instead of its own near-zero accelerations: three prints of 6 significant digits
// make a second difference of up to 4 x 5e-6 of a coordinate (the box's largest extent at most).
void GateAcceleration(const PairReducer& reduced, const ParityOptions& o, ParityReport* r) {
  Gate g = MakeGate("acceleration",
                    "per moving kind, |candidate / reference - 1| of the particles' acceleration "
                    "between paired frames (|x(t+dt) - 2x(t) + x(t-dt)| / dt^2), its median and "
                    "upper quartile over the kind averaged over the stencils; worst kind, the "
                    "larger",
                    NAN, o.gates.acceleration, "relative");
  PushAccelerationGate(std::move(g), reduced, r, [r](const AccelerationReduction::Kind& k) {
    const double n = double(k.stencils);
    const double floor = k.PrintedFloor(r->box_scale_cu);
    const double median[2] = {k.median_sum[0] / n, k.median_sum[1] / n};
    const double quartile[2] = {k.upper_quartile_sum[0] / n, k.upper_quartile_sum[1] / n};
    const double median_gap = (median[1] - median[0]) / std::max(median[0], floor);
    const double quartile_gap = (quartile[1] - quartile[0]) / std::max(quartile[0], floor);
    char detail[400];
    std::snprintf(detail, sizeof detail,
                  "%s over %zu stencils: median candidate %.4g, reference %.4g cu/s^2 (%+.1f%%), "
                  "upper quartile candidate %.4g, reference %.4g cu/s^2 (%+.1f%%)",
                  k.name, k.stencils, median[1], median[0], 100 * median_gap, quartile[1],
                  quartile[0], 100 * quartile_gap);
    return std::pair{std::max(std::abs(median_gap), std::abs(quartile_gap)), std::string(detail)};
  });
}

// The stencil at which one run's median acceleration stands highest above the other run's
// (StencilExcesses). A frame written displaced and the next one back (a glitch) makes
// the stencils around it a spike that the averages of `acceleration` dilute over the run. Honest
// runs whose chaos has diverged strike the floor or a wall a frame or two apart, so each run is
// measured against the other's neighbourhood, not its same stencil; and against at least the
// run's mean, since a stencil's median passes through zero (one particle's twice a period, a
// body's at rest).
void GateAccelerationStencil(const PairReducer& reduced, const ParityOptions& o, ParityReport* r) {
  Gate g = MakeGate("acceleration.worst_stencil",
                    "per moving kind, the most one run's median acceleration at a stencil of "
                    "three paired frames exceeds the other run's largest within " +
                        std::to_string(StencilExcesses::kStencilWindow) +
                        " stencils, over that median or the reference's mean over the run "
                        "(whichever is larger); worst kind",
                    NAN, o.gates.acceleration_stencil, "relative");
  PushAccelerationGate(std::move(g), reduced, r, [r](const AccelerationReduction::Kind& k) {
    const double n = double(k.stencils);
    const double mean = std::max(k.median_sum[0] / n, k.PrintedFloor(r->box_scale_cu));
    const StencilExcess worst = k.excesses.Worst(mean);
    char detail[320];
    std::snprintf(detail, sizeof detail,
                  "%s: %.3g at the stencil around reference frame %zu (median candidate %.4g, "
                  "reference %.4g cu/s^2; the reference's mean %.4g, %zu stencils)",
                  k.name, worst.value, worst.reference_frame, worst.median[1], worst.median[0],
                  k.median_sum[0] / n, k.stencils);
    return std::pair{worst.value, std::string(detail)};
  });
}

// Per moving kind, how far the candidate's frames between two of its paired frames stray
// outside the box its positions at the pair span, over the distance the reference's fastest
// particle of the kind covers in that interval (Excursions, PeakSpeed): the
// only gate that reads a finer candidate's frames between the pairs. An honest excursion is at
// most half the path, so at most 0.5 where the candidate is no faster than the reference. A
// reference whose kind barely moves is judged against the printed precision instead: two prints
// of 6 significant digits, 1e-5 of the box's largest extent, over its mean frame interval.
void GateUnpairedFrames(const PairReducer& reduced, const ParityOptions& o, ParityReport* r) {
  if (!reduced.has_moving_particles()) return;
  Gate g = MakeGate("unpaired_frames",
                    "per moving kind, the farthest a particle at a candidate frame between two "
                    "paired frames strays outside the box its positions at the pair span (largest "
                    "axis), over the distance the reference's fastest particle between two of its "
                    "frames covers in that interval; worst kind",
                    NAN, o.gates.unpaired_frames, "of the reference's reach");
  for (const SpeedKind& s : reduced.speeds()) {
    const PeakSpeed& ref = s.reference;
    const Excursions& cand = s.candidate;
    if (ref.intervals() == 0 || cand.unpaired_frames() == 0) continue;
    const double floor = InitialState::kPrintedDigitsRounding * r->box_scale_cu *
                         double(ref.intervals()) / ref.duration_s();
    const double value = cand.speed_cu_s() / std::max(ref.speed_cu_s(), floor);
    if (std::isnan(g.value) || !(value <= g.value)) g.value = std::isnan(value) ? INFINITY : value;
    char detail[400];
    std::snprintf(detail, sizeof detail,
                  "%s: particle %zu %.4g cu outside its box between the candidate's paired frames "
                  "%zu and %zu (%zu unpaired frames read); the reference's fastest %.4g cu/s "
                  "(particle %zu, frames %zu to %zu)",
                  s.name, cand.particle(), cand.excursion_cu(), cand.from_frame(), cand.to_frame(),
                  cand.unpaired_frames(), ref.speed_cu_s(), ref.particle(), ref.from_frame(),
                  ref.to_frame());
    g.detail += (g.detail.empty() ? "" : "; ") + std::string(detail);
  }
  if (std::isnan(g.value))
    g.detail =
        "the candidate has no frames between its paired ones (it is not logged more "
        "finely than the reference)";
  else
    Decide(&g);
  r->gates.push_back(g);
}

// At sample frames, the scene as well as the tracked scalar: each moving group's centroid
// distance against the box (the centroid_distance threshold), so a labelled frame whose picture
// is off fails even when the tracked particle happens to agree. Over all frames this is the
// centroid_distance gate itself, so it is added only for a sample.
void GateSampledGroups(const Pairs& pairs, const std::vector<std::size_t>& gated,
                       const PairReducer& reduced, const ParityOptions& o, ParityReport* r) {
  if (o.sample_frames.empty()) return;
  Gate g =
      MakeGate("frames.group_centroids", "worst 3-D group centroid distance at the gated frames", 0,
               o.gates.centroid_distance, "of the box");
  for (int group = 0; group < 2; ++group) {
    if (!reduced.HasSampleGroup(group)) continue;
    for (std::size_t k : gated) {
      const double d = reduced.SampleDistance(k, group);
      g.value = std::isfinite(d) ? std::max(g.value, d) : INFINITY;
      if (!(d < g.threshold.value))
        g.detail += std::string(g.detail.empty() ? "" : "; ") +
                    (group == 0 ? "elastic" : "liquid") + " at frame " +
                    std::to_string(pairs[k].first);
    }
  }
  Decide(&g);
  r->gates.push_back(g);
}

void MeasureSignals(const PairReducer& reduced, const ParityOptions& o, ParityReport* r) {
  const std::vector<double>& cand_time = reduced.candidate_time();
  const auto [lo, hi] = std::minmax_element(r->reference_series.begin(), r->reference_series.end());
  r->reference_range = *hi - *lo;
  r->scale_given = o.scale.has_value();
  r->scale = o.scale ? *o.scale : r->reference_range;
  if (!(r->scale > 0)) r->scale = 1.0;  // a constant reference: compare in absolute config units
  if (r->paired_time_s.size() < 2) return;
  r->reference_metrics = MeasureSignal(r->paired_time_s, r->reference_series);
  const SignalMetrics all_frames =
      reduced.resolved_series().size() == r->reference_series.size()
          ? r->reference_metrics
          : MeasureSignal(reduced.resolved_time(), reduced.resolved_series());
  r->reference_crossings_all_frames = all_frames.upward_crossings;
  r->reference_period_all_frames_s = all_frames.period_s;
  r->candidate_metrics = MeasureSignal(cand_time, r->candidate_series);
  r->period_gap = RelativeGap(r->reference_metrics.period_s, r->candidate_metrics.period_s);
  r->half_amplitude_gap =
      RelativeGap(r->reference_metrics.half_amplitude, r->candidate_metrics.half_amplitude);
  r->equilibrium_gap_cu = r->candidate_metrics.equilibrium - r->reference_metrics.equilibrium;
}

}  // namespace owval::compare::internal
