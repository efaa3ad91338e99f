#pragma once
// Parity of a candidate trajectory against a reference (design notes §4): the report a backend
// port must pass. Frames are paired by simulation time (PairFramesByTime), so files with
// different log steps, layouts or durations compare correctly, and every measure, on both sides,
// is taken over the two runs' common time window only. Both trajectories are read one pair of
// frames at a time (CompareFrameSources, issue 16): every gate is a reduction over the pairs in
// time order (the tracked scalar's series, per-particle distances, group centroids and extents,
// the last pair), so memory is O(particles) plus a few numbers a frame, whatever the length.
//
// Gates (each listed in the report with its value, threshold and the threshold's source):
//  - window: the common window must cover the reference's duration (every other gate is
//    measured over it only, so a candidate with one frame would otherwise agree with anything).
//  - sampling: the longest stretch between paired frames that skips reference frames must be
//    short (a candidate logged at two instants would otherwise be judged on those alone);
//    sampling.oscillation: and shorter than half the reference's period when it oscillates.
//    Only frames at the same time are paired (to 1% of the finer frame interval): a candidate
//    whose header claims another time step is not compared at the wrong instants.
//  - time_base: the candidate's frames evenly spaced in time (n/a below three frames).
//  - initial_state: the candidate at the reference's first frame equals it particle for
//    particle, to the printed precision (a run that starts elsewhere is another experiment).
//  - stale_frames: no paired frame at which the candidate's moving particles all stand where they
//    stood at the paired frame before while the reference's moved (a frame written twice).
//  - particle_types: the candidate's type codes equal the reference's (every other gate reads
//    the kinds from the reference).
//  - closest_approach: the reference's closest approach of two particles (one moving) over the
//    candidate's: pressure holds particles apart, so no honest pair comes ten times closer than
//    the reference's closest ever did (closest_approach.hpp, ParityGates::closest_approach).
//  - held_pair: per kind of pair, the distance within which the reference holds some pair for a
//    tenth of the paired frames over the candidate's: an honest near-encounter is brief, a leak
//    or an edit holds its pair close for the rest of the run (held_pairs.hpp,
//    ParityGates::held_pair).
//  - liquid_packing: the liquid's SPH kernel sum recomputed from positions (every particle a
//    neighbour), its median and upper quartile over the liquid averaged over the paired frames,
//    against the reference's: PCISPH holds the liquid at its rest density, and a liquid 3% less
//    dense moves no particle far enough for the motion gates (liquid_packing.hpp,
//    ParityGates::liquid_packing). Not applicable when the reference has no liquid.
//  - acceleration: per moving kind, the particles' acceleration between paired frames
//    (|x(t+dt) - 2x(t) + x(t-dt)| / dt^2), its median and upper quartile averaged over the
//    stencils, against the reference's: noise added to every frame raises it, a time-filtered
//    copy lowers it, and neither moves a particle far enough for the motion gates
//    (frame_acceleration.hpp, ParityGates::acceleration).
//  - acceleration.worst_stencil: the same medians stencil by stencil, each run's against the
//    other's nearby: a frame written displaced (and the next one back) spikes its stencils,
//    which the averages of `acceleration` dilute over the run (ParityGates::acceleration_stencil).
//  - unpaired_frames: a candidate logged more finely than the reference, per moving kind: how far
//    its frames between two paired frames stray outside the box of the pair, over the reference's
//    fastest reach in the interval: the one gate that reads those frames, where a frame written
//    aside was seen by nothing (ParityGates::unpaired_frames).
//  - elastic.bond_length: the elastic body's bonds (pairs within 1.5 times its lattice spacing
//    at the reference's first frame) as long as the reference's at every paired frame: a part of
//    the body out of shape, which the motion gates' 5% of the box lets through
//    (ParityGates::bond_length).
//  - boundary.fixed: the walls where the reference's are at every paired frame, to the printed
//    precision (initial_state's measure and threshold): no boundary particle is ever integrated.
//  - frames: |cand - ref| of the tracked scalar at each gated frame, divided by the reference's
//    range over the common window (or a stated scale): DD001's "delta < 5% of the reference
//    scale".
//  - period, half_amplitude: zero-crossing period and half-amplitude gaps. They apply only where
//    both signals oscillate: at least `min_crossings` upward mean crossings in each; otherwise
//    they are reported as not applicable (a dropped cube has no period), unless the reference
//    oscillates over its own frames and the paired frames do not show it: then they fail.
//  - For scenes whose detail is chaotic (demo1's sliding cube), per group (elastic, liquid) that
//    exists: the 3-D centroid distance (maximum over time), the bounding-box extents (maximum
//    over time and axes of |e_cand - e_ref| per axis), the final-state centroid distance; and
//    the mean per-particle distance of the moving particles at the first paired frame, averaged
//    over all paired frames, and at the last. All relative to the reference's box: its largest
//    extent for distances, its extent on the same axis for extents.
//  - Per kind of particle that exists (elastic, liquid, boundary): the worst single particle,
//    max over its particles and the paired frames of its 3-D distance, of the box (the means
//    above let one particle be anywhere).
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "owval/compare/gates.hpp"
#include "owval/compare/signal_metrics.hpp"
#include "owval/trajectory/frame_source.hpp"
#include "owval/trajectory/track.hpp"
#include "owval/trajectory/trajectory.hpp"

namespace owval::compare {

// Thresholds of every parity gate, each with its source. Defaults follow DD001 (5% of the
// reference scale); scenario manifests and flags override them (scenarios::ApplyManifestGates).
struct ParityGates {
  Threshold frame{0.05};              // fraction of the reference range
  Threshold period_gap{0.02};         // |T_cand - T_ref| / T_ref
  Threshold amplitude_gap{0.05};      // |A_cand - A_ref| / A_ref
  Threshold min_crossings{4};         // upward mean crossings both signals need for the above
  Threshold centroid_distance{0.05};  // fraction of the box's largest extent
  Threshold extent{0.05};             // fraction of the box's extent on that axis
  Threshold final_distance{0.05};     // fraction of the box's largest extent
  Threshold particle_distance{0.05};  // fraction of the box's largest extent
  // One particle's largest distance over the paired frames, per kind (elastic, liquid,
  // boundary): the particle_distance gates are means, which one far-off particle hardly moves.
  Threshold worst_particle{0.05};  // fraction of the box's largest extent
  // Scene gates, applied when the scene has the body they measure (body_gates.cpp):
  Threshold body_shape{0.05};  // worm span and cross-section diameter, relative to the reference
  Threshold membrane_liquid_fraction{0.05};  // |difference| of the liquid fraction above a sheet
  // The elastic body's bonds: pairs of elastic particles within 1.5 times the body's spacing
  // (the median distance from an elastic particle to its nearest elastic neighbour) of each other
  // at the reference's first frame; Sibernetic builds bodies on a lattice r0 apart, so these are
  // the nearest neighbours and the face diagonals. The value is the largest |length_cand -
  // length_ref| over the bonds and the paired frames, of that spacing; a length does not change
  // when the body moves or turns. The motion gates allow 5% of the box, 2.7 spacings in demo1:
  // one elastic particle written 2 spacings aside for the whole run, or a tenth of the body half
  // a spacing aside, passed every gate. Measured (docs/checklist.md, "elastic.bond_length"):
  // demo1 rerun with gravity changed by 1e-6, 0.22 (at the impact); a tenth of the body 0.5
  // spacing aside 0.53, one particle 2 spacings aside 2.13. Applies when the reference has a bond.
  Threshold bond_length{0.5};  // of the body's spacing
  // The part of the reference's duration outside the common window: a candidate that stops
  // early (or an interrupted run) is not judged on the stretch it happens to share.
  Threshold window{0.02};  // fraction of the reference's duration
  // The longest time between two paired frames that skips reference frames: the other gates see
  // only paired frames, so a candidate logged at two instants would be judged on those alone.
  Threshold sampling{0.05};  // fraction of the reference's duration
  // The same gap against the reference's own period, when it oscillates: half a period or more
  // cannot resolve the oscillation (Nyquist), and aliased samples of a wrong one can agree.
  Threshold sampling_period{0.5};  // fraction of the reference's period
  // The candidate's frames evenly spaced in time (an HDF5 /time column can relabel frames).
  Threshold time_base{0.01};  // departure of an interval from the mean interval, fraction
  // The candidate's first frame where the reference's is, particle for particle: a run of the
  // same configuration starts where the reference starts, to the files' printed precision.
  Threshold initial_state{1};  // worst coordinate's difference, of two 6-digit prints' rounding
  // The reference's closest approach of two particles (one moving) over the paired frames over
  // the candidate's. Pressure (PCISPH's density correction) holds particles apart at about r0,
  // so a run's closest pair is the rarest of many brief near-encounters. Where the share of
  // encounters closer than r grows as c r^(m+1) (m = 2 for pairs placed at random in 3-D, more
  // where pressure holds them apart), the closest of n has P(min > r) = exp(-n c r^(m+1))
  // (Weibull; Gumbel 1958, Statistics of Extremes), so two runs of the same physics over the
  // same frames give a ratio above k with probability 1 / (1 + k^(m+1)) <= 1 / (1 + k^3),
  // whatever n: 1e-3 at k = 10. A candidate whose closest pair is ten times closer than the
  // reference's ever was has particles pushed into each other (pressure failing, a constraint
  // leaking, an edit). Measured honest PCISPH reruns of demo1 (leapfrog, gravity changed by
  // 1e-6): 0.48-2.1, and test_energy's leapfrog 6.8 (another integrator: the closest yet);
  // XPBD's liquid, which clumps without Macklin & Mueller 2013's s_corr (the tensile
  // instability), fails at 104, and measures 0.56 with it (docs/checklist.md).
  Threshold closest_approach{10};  // reference distance / candidate distance
  // Per kind of pair (elastic-liquid, liquid-liquid, ...), the distance within which some pair
  // stays for a tenth of the paired frames, the reference's over the candidate's (held_pairs.hpp).
  // A pair held that long is no rare encounter: to stay within d over the window it must be
  // within d at each of the window's independent looks, each as likely as c·d^(m+1) near contact
  // (closest_approach's law), so for n looks two runs of the same physics give a ratio above k
  // with probability 1/(1 + k^(n(m+1))): at k = 2, 1/65 for n = 2, m = 1; 1/513 for n = 3, m = 2.
  // Measured (docs/checklist.md, "held_pair"): honest reruns of demo1 and test_energy (gravity
  // changed by 1e-6, leapfrog) 0.59-1.09; a liquid particle held at 0.1 r0 from its neighbour
  // 2.59-3.08 (demo1, test_energy, the worm), at 0.01 r0 27-32; XPBD's clumping liquid 5.19. One
  // held at 0.3 r0 passes: Sibernetic's own liquid holds pairs at 0.27-0.31 r0 that long.
  Threshold held_pair{2};  // reference's held distance / candidate's
  // The liquid's packing from positions alone (liquid_packing.hpp): at each liquid particle the
  // Wpoly6 kernel sum over every particle within h (twice the reference's median spacing at its
  // first paired frame: Sibernetic's h = 2 r0), its median and upper quartile over the liquid
  // (the bulk, not the free surface) averaged over the paired frames; the value is the larger
  // relative gap of the candidate's means to the reference's. PCISPH exists to hold the liquid
  // at its rest density: Sibernetic's own demo1 liquid has a per-frame median density of
  // 1045-1078 kg/m^3 (0.52% sd over frames 125-499; demo1_density_diag), and this statistic
  // varies by 0.44% sd over the same frames, so a mean over hundreds of frames of the same
  // physics differs by a fraction of that once the chaos has diverged. A liquid dilated by 1%
  // is 3% less dense: its kernel sum drops 2.3-3.0% (the particle's own term does not dilate).
  // Measured (docs/checklist.md, "liquid_packing"): honest PCISPH reruns (gravity changed by
  // 1e-6) of demo1 0.37-0.56% (six), demo1_1s 0.19%, test_energy 0.0003%, and test_energy's
  // leapfrog 0.66%; Sibernetic's runs dilated by 1% from frame 1 on 2.35-2.95% (demo1,
  // demo1_1s, test_energy, the worm), compressed by 1% 2.59%; dilated by 0.3% 0.75-0.90%, which
  // passes (within what honest runs differ by). demo1's leapfrog reruns fail (8.0%, 21.5%): their
  // liquid leaves the cube (and fails 10 other gates); so does XPBD's liquid, 5-11% less packed.
  Threshold liquid_packing{0.01};  // relative gap of the mean kernel sum, larger summary
  // The moving particles' acceleration between paired frames, from positions alone
  // (frame_acceleration.hpp): per kind (elastic, liquid) the median and upper quartile of
  // |x(t+dt) - 2 x(t) + x(t-dt)| / dt^2 over the kind's particles, averaged over the stencils;
  // the value is the worst kind's larger relative gap to the reference's. The forces set the
  // accelerations' distribution, as they set the packing, so runs of the same physics whose
  // chaos has diverged share it; noise added to every frame raises it, a time-filtered copy
  // lowers it. Measured: docs/checklist.md, "Attacks measured (round 7)".
  Threshold acceleration{0.25};  // relative gap of the mean acceleration, worst kind
  // The same medians stencil by stencil: the most one run's median at a stencil exceeds the
  // other run's largest within five stencils, relative to that or to the reference's mean over
  // the run. demo1's liquid written 1 r0 aside at one frame measures 13.9 (its elastic body
  // 38.0), honest reruns of demo1 1.36 at most (over 2,498 stencils), which the run's averages
  // above cannot tell apart. Measured: docs/checklist.md, "A frame written displaced".
  Threshold acceleration_stencil{4};  // relative excess, worst kind's worst stencil
  // A candidate logged more finely than the reference: per moving kind, the farthest a particle
  // at a frame between two paired frames strays outside the box its positions at the pair span,
  // over the distance the reference's fastest particle covers in the interval
  // (unpaired_frames.hpp). Half a path is the most an honest excursion can be (0.5 for a candidate
  // no faster than the reference); honest finer runs measure 0.15-0.24, and 0.70 over the worm's
  // first 3 frames (the reference's peak seen over two intervals). Measured: docs/checklist.md,
  // "unpaired_frames".
  Threshold unpaired_frames{2};  // excursion / the reference's reach, worst kind
};

// Every ParityGates threshold as users set it: a scenario manifest's "gates" key and an
// `owval compare` flag. The one list both readers use (scenarios::ApplyManifestGates, the CLI).
struct GateThresholdField {
  const char* manifest_key;  // "frame_threshold"
  const char* flag;          // "--threshold"
  Threshold ParityGates::*member;
  const char* help;  // what the threshold bounds
};
extern const std::vector<GateThresholdField> kGateThresholdFields;

// `field`'s help with its default: "frames gate (default 0.05)".
std::string GateThresholdHelp(const GateThresholdField& field);

// The thresholds of `gates` looser than DD001's defaults (ParityGates{}): every gate passes when
// its value is below its threshold, and min_crossings decides whether the oscillation gates apply
// at all, so a larger number is looser for every field. One line each: "worst_particle_threshold
// 0.3 (manifest; default 0.05)". Empty when none is.
std::vector<std::string> LoosenedThresholds(const ParityGates& gates);
// `gates` with every threshold looser than its default put back to the default (sources kept
// for the others): the caller's tightenings stay, its loosenings go.
ParityGates NoLooserThanDefaults(const ParityGates& gates);

struct ParityOptions {
  Track track;  // the tracked scalar of the frame gate
  // Reference frame indices to gate; empty means every reference frame that has a partner.
  std::vector<std::size_t> sample_frames;
  // Scale for |cand - ref| in cu; empty means the reference's range over the common window.
  std::optional<double> scale;
  ParityGates gates;
  bool quiet = true;  // no progress line (the CLI shows one on a terminal unless --quiet)
};

struct FrameParity {
  std::size_t reference_frame = 0, candidate_frame = 0;
  double time_s = 0;
  double reference_value = 0, candidate_value = 0;
  double relative_difference = 0;  // |cand - ref| / scale
  bool pass = true;
};

struct GroupDrift {
  std::string group;
  double final_centroid_distance_cu = 0;  // |centroid_cand - centroid_ref| at the last paired frame
  double final_offset_cu[3] = {0, 0, 0};  // centroid_cand - centroid_ref per axis, last frame
  double max_centroid_distance_cu = 0;
  double max_extent_difference_fraction = 0;  // max over frames, axes of |e_c - e_r| / box extent
  double final_extent_ratio[3] = {1, 1, 1};   // bounding-box extent cand/ref per axis, last frame
  // Not gates: what tells a turned body from a changed shape. A body that spins about the
  // vertical changes its bounding-box extents with its shape unchanged (demo1's reference cube
  // turns 37° about y on the floor). At the last paired frame: each run's rotation of the group
  // since the first paired frame (the angle of the best-fit rotation of its particles' offsets
  // from their centroid [Kabsch 1976]), and the extents in each run's own best-fit axes (that
  // rotation undone), cand/ref per axis. Only for a group of three particles or more.
  bool has_pose = false;
  double final_rotation_deg[2] = {0, 0};  // reference, candidate
  double final_body_extent_ratio[3] = {1, 1, 1};
};

struct ParityReport {
  std::string subject;  // e.g. "particle 0 y"
  double scale = 0;     // cu, for the frame gate
  // The caller's scale (--scale) instead of the reference's range: the report says so, with the
  // range it replaced, since a large scale loosens the frame gate as a large threshold would.
  bool scale_given = false;
  double reference_range = 0;  // cu, over the common window
  double box_scale_cu = 0;
  std::size_t paired_frames = 0;
  double common_window_start_s = 0, common_window_end_s = 0;
  std::vector<FrameParity> frames;  // the gated frames
  std::vector<std::size_t> failing_frames;
  // The tracked scalar at every paired frame (for plots of candidate - reference over time).
  std::vector<double> paired_time_s, reference_series, candidate_series;
  // Mean over moving particles of |x_cand - x_ref| (cu) at the first paired frame, averaged over
  // all paired frames, and at the last one.
  double l2_initial_cu = 0, l2_mean_cu = 0, l2_final_cu = 0;
  std::vector<GroupDrift> drift;
  SignalMetrics reference_metrics, candidate_metrics;  // over the common window
  // Upward mean crossings of the reference's tracked scalar over all its frames in the common
  // window, paired or not: when these reach min_crossings the oscillation gates apply, and fail
  // if the paired frames do not show the oscillation.
  std::size_t reference_crossings_all_frames = 0;
  std::optional<double> reference_period_all_frames_s;  // the same frames' zero-crossing period
  // Reference frames with a candidate frame within half a frame interval but at another time
  // (PairFramesByTime's near misses): not compared, since only frames at the same time are.
  std::size_t misaligned_pairs = 0;
  std::optional<double> period_gap, half_amplitude_gap, equilibrium_gap_cu;
  std::vector<Gate> gates;
  // An interrupted run's trajectory is compared over the frames it has, and the report says so.
  bool reference_partial = false, candidate_partial = false;

  bool pass() const { return AllApplicablePass(gates); }
  const Gate* gate(const std::string& name) const;
  std::string FailedGates() const { return FailedGateNames(gates); }

  nlohmann::json ToJson() const;
  std::string ToMarkdown() const;
  std::string ToTable() const;
};

// Throws InputError when the two trajectories have different particle counts, no frames in
// common time, or the track names nothing in them; and, from a file source, on a corrupt frame.
ParityReport CompareFrameSources(FrameSource& reference, FrameSource& candidate,
                                 const ParityOptions& options);
// The same on trajectories in memory (MemoryFrameSource: the same code, the same values).
ParityReport CompareTrajectories(const Trajectory& reference, const Trajectory& candidate,
                                 const ParityOptions& options);

// Phase 7's frame gates at options.sample_frames (owval frames, the checklist's item 5; owval
// compare --frames computes the same in its whole report): the tracked scalar's "frames" gate and,
// with sample frames, the moving groups' "frames.group_centroids". Every paired frame is read, so
// a corrupt one throws as CompareFrameSources does.
struct SampledFrameParity {
  Gate frames;                              // the tracked scalar's
  std::optional<Gate> group_centroids;      // with sample frames
  std::vector<std::size_t> failing_frames;  // reference frames where `frames` fails
  std::vector<Gate> gates() const;          // both, in that order
};
SampledFrameParity CompareSampledFrames(FrameSource& reference, FrameSource& candidate,
                                        const ParityOptions& options);

}  // namespace owval::compare
