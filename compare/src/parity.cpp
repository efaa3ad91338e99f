#include "owval/compare/parity.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <numbers>
#include <sstream>

#include <Eigen/Dense>

#include "body_gates.hpp"
#include "closest_approach.hpp"
#include "frame_acceleration.hpp"
#include "held_pairs.hpp"
#include "liquid_packing.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/format.hpp"
#include "owval/base/progress.hpp"
#include "owval/compare/metrics_json.hpp"
#include "stencil_excess.hpp"
#include "unpaired_frames.hpp"

namespace owval::compare {
namespace {

using Pairs = std::vector<std::pair<std::size_t, std::size_t>>;

std::vector<std::size_t> MovingParticles(const Trajectory& t) {
  std::vector<std::size_t> moving;
  for (std::size_t p = 0; p < t.particle_count(); ++p)
    if (KindOf(t.type[p]) != ParticleKind::kBoundary) moving.push_back(p);
  return moving;
}

double MeanParticleDistance(const FrameRef& a, const FrameRef& b,
                            const std::vector<std::size_t>& particles) {
  if (particles.empty()) return 0;
  double sum = 0;
  for (std::size_t p : particles) {
    const float* x = a.trajectory.position(a.frame, p);
    const float* y = b.trajectory.position(b.frame, p);
    sum += std::hypot(double(x[0]) - y[0], double(x[1]) - y[1], double(x[2]) - y[2]);
  }
  return sum / double(particles.size());
}

std::array<double, 3> Extent(const FrameRef& f, const std::vector<std::size_t>& group) {
  std::array<double, 3> out{};
  for (int a = 0; a < 3; ++a) {
    double lo = std::numeric_limits<double>::max(), hi = -lo;
    for (std::size_t p : group) {
      lo = std::min<double>(lo, f.trajectory.coordinate(f.frame, p, a));
      hi = std::max<double>(hi, f.trajectory.coordinate(f.frame, p, a));
    }
    out[a] = hi - lo;
  }
  return out;
}

double BoxScale(const Box& box) {
  const double s = std::max({box.extent(0), box.extent(1), box.extent(2)});
  return s > 0 ? s : 1.0;
}

// The group's particles' offsets from their centroid (cu), into `out` (its storage reused).
void Offsets(const FrameRef& f, const std::vector<std::size_t>& group,
             const std::array<double, 3>& centroid, std::vector<Eigen::Vector3d>* out) {
  out->resize(group.size());
  for (std::size_t k = 0; k < group.size(); ++k) {
    const float* x = f.trajectory.position(f.frame, group[k]);
    (*out)[k] = {x[0] - centroid[0], x[1] - centroid[1], x[2] - centroid[2]};
  }
}

// The rotation R that best maps the offsets `from` onto `to` (least squares, a proper rotation:
// Kabsch, Acta Cryst. A32, 922, 1976), its angle in degrees, and the extents of `to` with R
// undone, per axis of `from`'s frame.
struct BodyPose {
  double angle_deg = 0;
  std::array<double, 3> extent{};
};
BodyPose BestFitPose(const std::vector<Eigen::Vector3d>& from,
                     const std::vector<Eigen::Vector3d>& to) {
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (std::size_t p = 0; p < from.size(); ++p) covariance += from[p] * to[p].transpose();
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  if (!covariance.allFinite()) return {kNaN, {kNaN, kNaN, kNaN}};  // a blown-up run has no pose
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance,
                                              Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d sign = Eigen::Matrix3d::Identity();
  sign(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1 : 1;
  const Eigen::Matrix3d rotation = svd.matrixV() * sign * svd.matrixU().transpose();  // to ≈ R from
  BodyPose pose;
  pose.angle_deg =
      std::acos(std::clamp((rotation.trace() - 1) / 2, -1.0, 1.0)) * 180 / std::numbers::pi;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::max()), hi = -lo;
  for (const Eigen::Vector3d& x : to) {
    const Eigen::Vector3d body = rotation.transpose() * x;
    lo = lo.cwiseMin(body), hi = hi.cwiseMax(body);
  }
  for (int a = 0; a < 3; ++a) pose.extent[a] = to.empty() ? 0 : hi[a] - lo[a];
  return pose;
}

// One group's drift, accumulated pair by pair in time order.
struct DriftAccumulator {
  std::vector<std::size_t> members;
  GroupDrift d;
  // Offsets at the first paired frame and at the latest one; the pose is fitted once, at the end.
  std::vector<Eigen::Vector3d> first_ref, first_cand, last_ref, last_cand;

  void Observe(const FrameRef& ref, const FrameRef& cand, const Box& box) {
    const auto a = Centroid(ref.trajectory, ref.frame, members),
               b = Centroid(cand.trajectory, cand.frame, members);
    ObservePose(ref, cand, a, b);
    const double dist = std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
    d.max_centroid_distance_cu = std::max(d.max_centroid_distance_cu, dist);
    d.final_centroid_distance_cu = dist;
    for (int ax = 0; ax < 3; ++ax) d.final_offset_cu[ax] = b[ax] - a[ax];
    const auto er = Extent(ref, members), ec = Extent(cand, members);
    for (int ax = 0; ax < 3; ++ax) {
      const double extent = box.extent(ax) > 0 ? box.extent(ax) : 1.0;
      d.max_extent_difference_fraction =
          std::max(d.max_extent_difference_fraction, std::abs(ec[ax] - er[ax]) / extent);
      d.final_extent_ratio[ax] = er[ax] > 0 ? ec[ax] / er[ax] : (ec[ax] > 0 ? INFINITY : 1);
    }
  }

  void ObservePose(const FrameRef& ref, const FrameRef& cand, const std::array<double, 3>& a,
                   const std::array<double, 3>& b) {
    if (members.size() < 3) return;  // one or two points have no orientation to speak of
    const bool first = first_ref.empty();
    Offsets(ref, members, a, first ? &first_ref : &last_ref);
    Offsets(cand, members, b, first ? &first_cand : &last_cand);
  }

  // After the last pair: the pose at the last paired frame, when there is one after the first.
  void FinishPose() {
    if (last_ref.empty()) return;
    const BodyPose r = BestFitPose(first_ref, last_ref);
    const BodyPose c = BestFitPose(first_cand, last_cand);
    d.has_pose = true;
    d.final_rotation_deg[0] = r.angle_deg, d.final_rotation_deg[1] = c.angle_deg;
    for (int ax = 0; ax < 3; ++ax)
      d.final_body_extent_ratio[ax] =
          r.extent[ax] > 0 ? c.extent[ax] / r.extent[ax] : (c.extent[ax] > 0 ? INFINITY : 1);
  }
};

// The worst single particle of one kind: max over its particles and the paired frames of
// |x_cand - x_ref| (cu), and where. The particle_distance gates average over every moving
// particle, so one particle sent far away (to a wall, frozen in the air, swapped with another)
// moved demo1's mean by 0.1% of the box and passed; boundary particles were not looked at at all
// (one_sprig's spring anchor moved 10 cu passed).
struct WorstParticle {
  const char* group;
  std::vector<std::size_t> members;
  double distance_cu = 0;
  std::size_t particle = 0, reference_frame = 0;

  void Observe(const FrameRef& ref, const FrameRef& cand, std::size_t reference_frame_index) {
    double worst_squared = distance_cu * distance_cu;
    for (std::size_t p : members) {
      const float* x = ref.trajectory.position(ref.frame, p);
      const float* y = cand.trajectory.position(cand.frame, p);
      const double dx = double(y[0]) - x[0], dy = double(y[1]) - x[1], dz = double(y[2]) - x[2];
      double squared = dx * dx + dy * dy + dz * dz;
      if (!std::isfinite(squared)) squared = INFINITY;  // a NaN is the worst of all
      if (squared > worst_squared) {
        worst_squared = squared;
        distance_cu = std::sqrt(squared);
        particle = p, reference_frame = reference_frame_index;
      }
    }
  }
};

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

// The closest approach of two particles (one of them moving) over the paired frames, in each
// run (closest_approach.hpp): pressure holds an honest run's particles apart, so a candidate
// whose particles come much closer than the reference's ever do has particles put where the
// physics cannot put them (demo1: a liquid particle on its neighbour's place from
// frame 1 on passed every distance gate, 4.2 cu being less than honest ports' own differences).
struct ClosestApproach {
  internal::ClosestPair reference{INFINITY}, candidate{INFINITY};
  std::size_t reference_frame = 0, candidate_reference_frame = 0;

  // The last frame's closest distances: the next frame's search starts from a cell a little
  // wider (one sort a frame where the scene changes little; it widens itself when not).
  double last_reference_cu = 0, last_candidate_cu = 0;

  static double CellFrom(double last_cu, double fallback_cu) {
    return std::isfinite(last_cu) && last_cu > 0 ? 1.5 * last_cu : fallback_cu;
  }

  // `known`: each run's closest pair within the held pairs' cap (HeldPairs::Observe), searched
  // for here only when there is none (half a demo1 compare was the two searches).
  void Observe(const FrameRef& ref, const FrameRef& cand, const std::vector<std::size_t>& moving,
               double cell_cu, std::size_t reference_frame_index,
               const std::array<internal::ClosestPair, 2>& known) {
    const internal::ClosestPair r =
        std::isfinite(known[0].distance_cu)
            ? known[0]
            : internal::FindClosestPair(ref, moving, CellFrom(last_reference_cu, cell_cu));
    const internal::ClosestPair c =
        std::isfinite(known[1].distance_cu)
            ? known[1]
            : internal::FindClosestPair(cand, moving, CellFrom(last_candidate_cu, cell_cu));
    last_reference_cu = r.distance_cu, last_candidate_cu = c.distance_cu;
    if (r.distance_cu < reference.distance_cu)
      reference = r, reference_frame = reference_frame_index;
    if (c.distance_cu < candidate.distance_cu)
      candidate = c, candidate_reference_frame = reference_frame_index;
  }
};

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

// How tightly each run's liquid is packed (liquid_packing.hpp), per paired frame, reduced to
// the mean over the paired frames of each summary and the frame where the two runs differ most.
struct PackingReduction {
  double support_cu = 0;  // twice the reference's median spacing at its first paired frame
  std::size_t frames = 0;
  double median_sum[2] = {0, 0}, upper_quartile_sum[2] = {0, 0};  // reference, candidate
  // The paired frame whose upper quartiles differ most, relatively, and both runs' values there.
  double worst_frame_gap = -1;
  std::size_t worst_frame = 0;
  internal::PackingSummary worst[2];

  void Observe(const internal::PackingSummary& ref, const internal::PackingSummary& cand,
               std::size_t reference_frame) {
    ++frames;
    median_sum[0] += ref.median, median_sum[1] += cand.median;
    upper_quartile_sum[0] += ref.upper_quartile, upper_quartile_sum[1] += cand.upper_quartile;
    const double gap = std::abs(cand.upper_quartile / ref.upper_quartile - 1);
    if (!(gap <= worst_frame_gap))
      worst_frame_gap = gap, worst_frame = reference_frame, worst[0] = ref, worst[1] = cand;
  }
};

// How hard each run pushes its moving particles between paired frames (frame_acceleration.hpp),
// per kind (elastic, liquid): each summary's mean over the stencils both runs complete (three
// paired frames evenly spaced in time), so both are measured at the same instants and intervals
// whatever their own log steps; and each stencil's two medians (acceleration.worst_stencil).
struct AccelerationReduction {
  // A second difference of three prints of 6 significant digits, as a fraction of the box's
  // largest extent: 4 x 5e-6, rounded up. Below it a reference's particles barely move.
  static constexpr double kPrintedSecondDifference = 2e-5;
  struct Kind {
    Kind(const char* kind_name, const std::vector<std::size_t>& members)
        : name(kind_name),
          runs{internal::FrameAcceleration(members), internal::FrameAcceleration(members)} {}
    const char* name;
    internal::FrameAcceleration runs[2];  // reference, candidate
    std::size_t stencils = 0;
    double median_sum[2] = {0, 0}, upper_quartile_sum[2] = {0, 0};  // cu/s^2
    double inverse_interval_squared_sum = 0;                        // 1/s^2, for the floor
    // Each stencil's two medians (reference, candidate) against the other run's nearby, for
    // acceleration.worst_stencil: a window of stencils and the pairs that can still be worst.
    internal::StencilExcesses excesses;
    // Three prints' rounding over the stencils' mean dt^2 (cu/s^2): what a reference at rest
    // measures, for the box's largest extent `box_scale_cu`.
    double PrintedFloor(double box_scale_cu) const {
      return kPrintedSecondDifference * box_scale_cu * inverse_interval_squared_sum /
             double(stencils);
    }
  };
  std::vector<Kind> kinds;
  std::size_t previous_frame = 0;  // the reference frame of the pair observed before

  // The pair at `reference_frame`, at `time_s`: the last frame of a stencil.
  void Observe(const FrameRef& ref, const FrameRef& cand, double time_s,
               std::size_t reference_frame) {
    const std::size_t middle = previous_frame;
    previous_frame = reference_frame;
    for (Kind& k : kinds) {
      const auto r = k.runs[0].Observe(ref, time_s), c = k.runs[1].Observe(cand, time_s);
      if (!r || !c) continue;
      ++k.stencils;
      k.median_sum[0] += r->median, k.median_sum[1] += c->median;
      k.upper_quartile_sum[0] += r->upper_quartile, k.upper_quartile_sum[1] += c->upper_quartile;
      k.inverse_interval_squared_sum += 1 / (r->interval_s * r->interval_s);
      k.excesses.Push(middle, r->median, c->median);
    }
  }
};

// Per moving kind (unpaired_frames.hpp): the reference's peak speed over its frames in the common
// window, and the excursions of the candidate's frames between its paired ones.
struct SpeedKind {
  SpeedKind(const char* kind_name, const std::vector<std::size_t>& members)
      : name(kind_name), reference(members), candidate(members) {}
  const char* name;
  internal::PeakSpeed reference;
  internal::Excursions candidate;
};

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
              ParityReport* r, Scope scope = Scope::kEveryGate)
      : scope_(scope),
        ref_(ref),
        o_(o),
        r_(r),
        pairs_(pairs),
        moving_(MovingParticles(ref)),
        sampled_(pairs.size(), false),
        bodies_(ref, cand, ref_frames, o.gates) {
    for (std::size_t p : moving_)
      if (KindOf(ref.type[p]) == ParticleKind::kLiquid) liquid_.push_back(p);
    for (const auto& [name, kind] : {std::pair{"elastic", ParticleKind::kElastic},
                                     std::pair{"liquid", ParticleKind::kLiquid}}) {
      std::vector<std::size_t> members;
      for (std::size_t p : moving_)
        if (KindOf(ref.type[p]) == kind) members.push_back(p);
      if (members.empty()) continue;
      acceleration_.kinds.emplace_back(name, members);
      speeds_.emplace_back(name, members);
    }
    for (const char* group : {"elastic", "liquid"}) {
      DriftAccumulator g;
      g.d.group = group;
      for (std::size_t p : moving_)
        if (KindName(KindOf(ref.type[p])) == std::string(group)) g.members.push_back(p);
      if (!g.members.empty()) drift_.push_back(std::move(g));
    }
    if (!o.sample_frames.empty())
      for (std::size_t k : gated) sampled_[k] = true;
    tracked_members_ = o.track.group.empty() ? std::vector<std::size_t>{o.track.particle}
                                             : GroupIndices(ref, o.track.group);
    for (const char* group : {"elastic", "liquid"}) {
      const ParticleKind kind = group[0] == 'e' ? ParticleKind::kElastic : ParticleKind::kLiquid;
      sample_groups_.push_back(ref.count(kind) == 0 ? std::vector<std::size_t>{}
                                                    : GroupIndices(ref, group));
    }
    for (const auto& [group, kind] :
         {std::pair{"elastic", ParticleKind::kElastic}, std::pair{"liquid", ParticleKind::kLiquid},
          std::pair{"boundary", ParticleKind::kBoundary}}) {
      WorstParticle w{group, {}};
      for (std::size_t p = 0; p < ref.particle_count(); ++p)
        if (KindOf(ref.type[p]) == kind) w.members.push_back(p);
      if (kind == ParticleKind::kBoundary) boundary_ = w.members;
      if (!w.members.empty()) worst_.push_back(std::move(w));
    }
  }

  void Observe(std::size_t k, const FrameRef& a, const FrameRef& b, double cand_time) {
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
    const std::array<internal::ClosestPair, 2> known = ObserveHeldPairs(k, a, b);
    if (!moving_.empty())
      closest_.Observe(a, b, moving_, kClosestApproachCell * r_->box_scale_cu, pairs_[k].first,
                       known);
    ObservePacking(k, a, b);
    acceleration_.Observe(a, b, ref_.time_s[pairs_[k].first], pairs_[k].first);
    if (sampled_[k]) ObserveSample(k, a, b);
    bodies_.Observe(a, b, r_->box_scale_cu);
  }

  // After the last pair.
  void Finish() {
    if (scope_ == Scope::kSampledFrameGates) return;
    r_->l2_mean_cu = l2_sum_ / double(pairs_.size());
    for (DriftAccumulator& g : drift_) {
      g.FinishPose();
      r_->drift.push_back(g.d);
    }
  }
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
  internal::BodyGates& bodies() { return bodies_; }
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
  const std::optional<internal::HeldPairs>& held_reference() const { return held_[0]; }
  const std::optional<internal::HeldPairs>& held_candidate() const { return held_[1]; }
  double held_spacing_cu() const { return held_spacing_cu_; }
  bool has_moving_particles() const { return !moving_.empty(); }
  bool has_liquid() const { return !liquid_.empty(); }
  const PackingReduction& packing() const { return packing_; }
  const AccelerationReduction& acceleration() const { return acceleration_; }
  const std::vector<SpeedKind>& speeds() const { return speeds_; }

 private:
  void ObserveSample(std::size_t k, const FrameRef& a, const FrameRef& b) {
    std::array<double, 2> d{0, 0};
    for (int g = 0; g < 2; ++g) {
      if (sample_groups_[g].empty()) continue;
      const auto x = Centroid(a.trajectory, a.frame, sample_groups_[g]),
                 y = Centroid(b.trajectory, b.frame, sample_groups_[g]);
      d[g] = std::hypot(x[0] - y[0], x[1] - y[1], x[2] - y[2]) / r_->box_scale_cu;
    }
    sample_distance_[k] = d;
  }

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
  std::array<internal::ClosestPair, 2> ObserveHeldPairs(std::size_t k, const FrameRef& a,
                                                        const FrameRef& b) {
    constexpr internal::ClosestPair kNone{std::numeric_limits<double>::infinity()};
    if (moving_.empty()) return {kNone, kNone};
    if (k == 0) {
      held_spacing_cu_ =
          internal::MedianNearestSpacing(a, moving_, kClosestApproachCell * r_->box_scale_cu);
      if (!(held_spacing_cu_ > 0)) return {kNone, kNone};
      const std::size_t hold = std::max<std::size_t>(3, pairs_.size() / 10);
      for (auto& h : held_) h.emplace(held_spacing_cu_ / 2, hold);
    }
    if (!held_[0]) return {kNone, kNone};
    return {held_[0]->Observe(a, moving_, k), held_[1]->Observe(b, moving_, k)};
  }
  std::optional<internal::HeldPairs> held_[2];
  double held_spacing_cu_ = 0;
  // The liquid's packing in each run, with a support of twice the reference's median spacing at
  // its first paired frame (Sibernetic's h = 2 r0, its particles placed r0 apart).
  void ObservePacking(std::size_t k, const FrameRef& a, const FrameRef& b) {
    if (liquid_.empty()) return;
    if (k == 0) packing_.support_cu = 2 * held_spacing_cu_;
    if (!(packing_.support_cu > 0)) return;
    const internal::PackingSummary x = internal::MeasurePacking(a, liquid_, packing_.support_cu);
    const internal::PackingSummary y = internal::MeasurePacking(b, liquid_, packing_.support_cu);
    packing_.Observe(x, y, pairs_[k].first);
  }
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
  internal::BodyGates bodies_;
};

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

// The candidate's held pairs against the reference's (HeldPairs), kind of pair by kind: the
// value is the reference's held distance over the candidate's, worst kind, so a candidate that
// holds a liquid pair k times closer than the reference ever holds one for a tenth of the run
// measures k. A kind the reference never holds within the cap counts as held at the cap.
struct HeldWorst {
  double ratio = 0;
  int kind = -1;
};
HeldWorst WorstHeldKind(const internal::HeldPairs& ref, const internal::HeldPairs& cand) {
  HeldWorst worst;
  for (int c = 0; c < internal::kPairKinds; ++c) {
    const int jc = cand.held()[c].level, jr = std::max(ref.held()[c].level, 0);
    if (jc < 0) continue;
    const double ratio = std::exp2(double(jc - jr) / internal::HeldPairs::kLevelsPerOctave);
    if (ratio > worst.ratio) worst = {ratio, c};
  }
  return worst;
}

std::string HeldDetail(const Trajectory& ref, const Pairs& pairs, const internal::HeldPairs& h,
                       int kind, const char* who) {
  const internal::HeldPairs::Held& held = h.held()[kind];
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
    g.detail = std::string(internal::PairKindName(worst.kind)) + ": " +
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
// (internal::StencilExcesses). A frame written displaced and the next one back (a glitch) makes
// the stencils around it a spike that the averages of `acceleration` dilute over the run. Honest
// runs whose chaos has diverged strike the floor or a wall a frame or two apart, so each run is
// measured against the other's neighbourhood, not its same stencil; and against at least the
// run's mean, since a stencil's median passes through zero (one particle's twice a period, a
// body's at rest).
void GateAccelerationStencil(const PairReducer& reduced, const ParityOptions& o, ParityReport* r) {
  Gate g = MakeGate("acceleration.worst_stencil",
                    "per moving kind, the most one run's median acceleration at a stencil of "
                    "three paired frames exceeds the other run's largest within " +
                        std::to_string(internal::StencilExcesses::kStencilWindow) +
                        " stencils, over that median or the reference's mean over the run "
                        "(whichever is larger); worst kind",
                    NAN, o.gates.acceleration_stencil, "relative");
  PushAccelerationGate(std::move(g), reduced, r, [r](const AccelerationReduction::Kind& k) {
    const double n = double(k.stencils);
    const double mean = std::max(k.median_sum[0] / n, k.PrintedFloor(r->box_scale_cu));
    const internal::StencilExcess worst = k.excesses.Worst(mean);
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
// particle of the kind covers in that interval (internal::Excursions, internal::PeakSpeed): the
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
    const internal::PeakSpeed& ref = s.reference;
    const internal::Excursions& cand = s.candidate;
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

const Gate* ParityReport::gate(const std::string& name) const {
  for (const Gate& g : gates)
    if (g.name == name) return &g;
  return nullptr;
}

namespace {
nlohmann::json Opt(const std::optional<double>& v) {
  return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}

// The sampled frames' parity, one object a frame.
nlohmann::json FramesJson(const std::vector<FrameParity>& frames) {
  nlohmann::json frames_json = nlohmann::json::array();
  for (const FrameParity& f : frames)
    frames_json.push_back({{"reference_frame", f.reference_frame},
                           {"candidate_frame", f.candidate_frame},
                           {"time_s", f.time_s},
                           {"reference_value_cu", f.reference_value},
                           {"candidate_value_cu", f.candidate_value},
                           {"relative_difference", f.relative_difference},
                           {"pass", f.pass}});
  return frames_json;
}

// Each group's drift, one object a group; the pose fields null for a group without a pose.
nlohmann::json DriftJson(const std::vector<GroupDrift>& drift) {
  nlohmann::json drift_json = nlohmann::json::array();
  for (const GroupDrift& d : drift)
    drift_json.push_back(
        {{"group", d.group},
         {"final_centroid_distance_cu", d.final_centroid_distance_cu},
         {"max_centroid_distance_cu", d.max_centroid_distance_cu},
         {"max_extent_difference_of_box", d.max_extent_difference_fraction},
         {"final_extent_ratio_xyz",
          {d.final_extent_ratio[0], d.final_extent_ratio[1], d.final_extent_ratio[2]}},
         {"final_rotation_deg", d.has_pose ? nlohmann::json{{"reference", d.final_rotation_deg[0]},
                                                            {"candidate", d.final_rotation_deg[1]}}
                                           : nlohmann::json()},
         {"final_body_extent_ratio_xyz",
          d.has_pose ? nlohmann::json{d.final_body_extent_ratio[0], d.final_body_extent_ratio[1],
                                      d.final_body_extent_ratio[2]}
                     : nlohmann::json()}});
  return drift_json;
}
}  // namespace

// One key a field: a table, kept whole so that the JSON's shape reads in one place.
nlohmann::json ParityReport::ToJson() const {
  return {{"subject", subject},
          {"scale_cu", scale},
          {"scale_given", scale_given},
          {"reference_range_cu", reference_range},
          {"box_scale_cu", box_scale_cu},
          {"paired_frames", paired_frames},
          {"common_window_s", {common_window_start_s, common_window_end_s}},
          {"gates", compare::ToJson(gates)},
          {"failed_gates", FailedGates()},
          {"frames", FramesJson(frames)},
          {"failing_frames", failing_frames},
          {"per_particle_distance_cu",
           {{"initial", l2_initial_cu}, {"mean", l2_mean_cu}, {"final", l2_final_cu}}},
          {"group_drift", DriftJson(drift)},
          {"reference_metrics", compare::ToJson(reference_metrics)},
          {"candidate_metrics", compare::ToJson(candidate_metrics)},
          {"gaps",
           {{"period_relative", Opt(period_gap)},
            {"half_amplitude_relative", Opt(half_amplitude_gap)},
            {"equilibrium_cu", Opt(equilibrium_gap_cu)}}},
          {"reference_crossings_all_frames", reference_crossings_all_frames},
          {"reference_period_all_frames_s", Opt(reference_period_all_frames_s)},
          {"misaligned_pairs", misaligned_pairs},
          {"reference_partial", reference_partial},
          {"candidate_partial", candidate_partial},
          {"pass", pass()}};
}

namespace {
std::string PartialNotes(const ParityReport& r, const char* prefix) {
  std::string notes;
  for (const auto& [side, partial] :
       {std::pair{"reference", r.reference_partial}, std::pair{"candidate", r.candidate_partial}})
    if (partial)
      notes += std::string(prefix) + "note: the " + side +
               " is partial (an interrupted run's): compared over the frames it has\n";
  return notes;
}
}  // namespace

std::string ParityReport::ToMarkdown() const {
  std::ostringstream s;
  s << "### Parity: " << subject << " — " << (pass() ? "PASS" : "FAIL");
  if (!pass()) s << " (failed: " << FailedGates() << ")";
  s << "\n\n- paired frames: " << paired_frames << ", common window " << common_window_start_s
    << " s to " << common_window_end_s << " s\n- frame-gate scale: " << scale
    << (scale_given ? " cu (GIVEN by the caller, --scale; the reference range is " +
                          FormatNumber(reference_range, 4) + " cu)"
                    : std::string(" cu (reference range)"))
    << "; box scale: " << box_scale_cu << " cu\n"
    << PartialNotes(*this, "- ") << "\n";
  s << GatesMarkdownTable(gates);
  return s.str();
}

std::string ParityReport::ToTable() const {
  std::ostringstream s;
  s << "parity of " << subject << ": " << (pass() ? "PASS" : "FAIL");
  if (!pass()) s << " (failed: " << FailedGates() << ")";
  s << "\n  paired frames " << paired_frames << " over " << common_window_start_s << " s to "
    << common_window_end_s << " s; frame scale " << scale << " cu"
    << (scale_given
            ? " (GIVEN by --scale; reference range " + FormatNumber(reference_range) + " cu)"
            : std::string())
    << ", box scale " << box_scale_cu << " cu\n"
    << PartialNotes(*this, "  ");
  s << GatesTextTable(gates);
  s << "  particle distance (cu): initial " << l2_initial_cu << ", mean " << l2_mean_cu
    << ", final " << l2_final_cu << "\n";
  return s.str();
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

using G = ParityGates;
const std::vector<GateThresholdField> kGateThresholdFields = {
    {"frame_threshold", "--threshold", &G::frame,
     "frames gate: |cand - ref| / the reference's range of the tracked scalar at each gated "
     "frame; frames.position: of its particle's (or centroid's) 3-D position on the same scale"},
    {"period_gap_threshold", "--period-gap", &G::period_gap,
     "period gate: the relative gap of the tracked signal's periods"},
    {"amplitude_gap_threshold", "--amplitude-gap", &G::amplitude_gap,
     "half_amplitude gate: the relative gap of the half-amplitudes"},
    {"min_crossings", "--min-crossings", &G::min_crossings,
     "Upward crossings both signals need for the oscillation gates"},
    {"centroid_distance_threshold", "--centroid-threshold", &G::centroid_distance,
     "centroid_distance gates (elastic, liquid) and worm.centre_of_mass: the centroids' "
     "largest distance over time, fraction of the box"},
    {"extent_threshold", "--extent-threshold", &G::extent,
     "extent gates (elastic, liquid): the largest |extent difference| per axis, fraction of "
     "the box extent"},
    {"final_distance_threshold", "--final-threshold", &G::final_distance,
     "final_distance gates (elastic, liquid): the centroids' distance at the last frame, "
     "fraction of the box"},
    {"particle_distance_threshold", "--particle-threshold", &G::particle_distance,
     "particle_distance.initial/mean/final gates: the moving particles' distances, fraction "
     "of the box"},
    {"worst_particle_threshold", "--worst-particle-threshold", &G::worst_particle,
     "worst_particle gates (elastic, liquid, boundary): one particle's largest distance, "
     "fraction of the box"},
    {"body_shape_threshold", "--body-threshold", &G::body_shape,
     "worm.span, worm.cross_section_diameter and worm.ring_diameter gates, relative"},
    {"membrane_liquid_fraction_threshold", "--membrane-threshold", &G::membrane_liquid_fraction,
     "liquid.fraction_above_membrane gate: the difference of the fractions"},
    {"bond_length_threshold", "--bond-length-threshold", &G::bond_length,
     "elastic.bond_length gate: the largest difference of a bond's length (elastic pairs within "
     "1.5 spacings at the reference's first frame), of the body's spacing"},
    {"window_threshold", "--window-threshold", &G::window,
     "window gate: the reference's duration outside the common window, fraction"},
    {"sampling_threshold", "--sampling-threshold", &G::sampling,
     "sampling gate: the longest time between paired frames that skips reference frames, "
     "fraction of the reference's duration"},
    {"sampling_period_threshold", "--sampling-period-threshold", &G::sampling_period,
     "sampling.oscillation gate: the same gap, fraction of the reference's own period"},
    {"time_base_threshold", "--time-base-threshold", &G::time_base,
     "time_base gate: a candidate frame interval's departure from the mean, fraction"},
    {"initial_state_threshold", "--initial-state-threshold", &G::initial_state,
     "initial_state gate: the candidate's worst coordinate at the reference's first frame, in "
     "units of the rounding of two 6-significant-digit prints"},
    {"closest_approach_threshold", "--closest-approach-threshold", &G::closest_approach,
     "closest_approach gate: how many times closer than the reference's closest approach two "
     "of the candidate's particles (one moving) may come"},
    {"held_pair_threshold", "--held-pair-threshold", &G::held_pair,
     "held_pair gate: how many times closer than the reference holds a pair of a kind for a "
     "tenth of the paired frames the candidate may hold one"},
    {"liquid_packing_threshold", "--liquid-packing-threshold", &G::liquid_packing,
     "liquid_packing gate: the relative gap of the liquid's mean kernel sum (median, upper "
     "quartile) to the reference's"},
    {"acceleration_threshold", "--acceleration-threshold", &G::acceleration,
     "acceleration gate: the relative gap of the moving particles' mean acceleration between "
     "frames (median, upper quartile; worst kind) to the reference's"},
    {"acceleration_stencil_threshold", "--acceleration-stencil-threshold", &G::acceleration_stencil,
     "acceleration.worst_stencil gate: the most one run's median acceleration at a stencil of "
     "three paired frames exceeds the other's nearby, relative (a frame written displaced)"},
    {"unpaired_frames_threshold", "--unpaired-frames-threshold", &G::unpaired_frames,
     "unpaired_frames gate: how far a finer candidate's frames between two paired frames stray "
     "outside the box of the pair, of the reference's fastest reach over the interval"}};

std::string GateThresholdHelp(const GateThresholdField& field) {
  return std::string(field.help) + " (default " +
         FormatNumber((ParityGates{}.*field.member).value) + ")";
}

std::vector<std::string> LoosenedThresholds(const ParityGates& gates) {
  const ParityGates defaults;
  std::vector<std::string> loosened;
  for (const GateThresholdField& field : kGateThresholdFields) {
    const Threshold& given = gates.*field.member;
    const double default_value = (defaults.*field.member).value;
    if (!(given.value <= default_value))
      loosened.push_back(std::string(field.manifest_key) + " " + FormatNumber(given.value) + " (" +
                         SourceName(given.source) + "; default " + FormatNumber(default_value) +
                         ")");
  }
  return loosened;
}

ParityGates NoLooserThanDefaults(const ParityGates& gates) {
  const ParityGates defaults;
  ParityGates out = gates;
  for (const GateThresholdField& field : kGateThresholdFields)
    if (!((gates.*field.member).value <= (defaults.*field.member).value))
      out.*field.member = defaults.*field.member;
  return out;
}

}  // namespace owval::compare
