#include "body_gates.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "held_pairs.hpp"
#include "neighbour_grid.hpp"
#include "owval/kinematics/body_shape.hpp"
#include "owval/kinematics/midline.hpp"

namespace owval::compare::internal {
namespace {

double RelativeDifference(double reference, double candidate) {
  return std::abs(candidate / reference - 1);
}

// Every elastic particle within 1% of the box height of one plane, liquid present: a sheet.
bool IsMembraneScene(const Trajectory& t, FrameSource& frames) {
  if (t.count(ParticleKind::kElastic) == 0 || t.count(ParticleKind::kLiquid) == 0 ||
      t.frame_count() == 0)
    return false;
  const std::vector<std::size_t> elastic = GroupIndices(t, "elastic");
  const FrameRef first = frames.Frame(0);
  double lo = INFINITY, hi = -INFINITY;
  for (std::size_t i : elastic) {
    lo = std::min(lo, double(first.trajectory.coordinate(first.frame, i, 1)));
    hi = std::max(hi, double(first.trajectory.coordinate(first.frame, i, 1)));
  }
  return hi - lo < 0.01 * (t.box.ymax - t.box.ymin);
}

double LiquidFractionAbove(const FrameRef& f, const std::vector<std::size_t>& liquid,
                           const std::vector<std::size_t>& elastic) {
  const double sheet_y = Centroid(f.trajectory, f.frame, elastic)[1];
  std::size_t above = 0;
  for (std::size_t i : liquid) above += f.trajectory.coordinate(f.frame, i, 1) > sheet_y;
  return double(above) / double(liquid.size());
}

}  // namespace

BodyGates::BodyGates(const Trajectory& ref, const Trajectory& cand, FrameSource& ref_frames,
                     const ParityGates& gates) {
  worm_ = kinematics::IsWorm(ref) && kinematics::IsWorm(cand);
  membrane_ = IsMembraneScene(ref, ref_frames);
  com_ = MakeGate("worm.centre_of_mass", "max over time of the worm's centre-of-mass distance", 0,
                  gates.centroid_distance, "of the box");
  span_ = MakeGate("worm.span", "max over time of the midline length's relative difference", 0,
                   gates.body_shape, "of the reference's");
  diameter_ = MakeGate("worm.cross_section_diameter",
                       "max over time of the mid-body cross-section diameter's relative difference",
                       0, gates.body_shape, "of the reference's");
  ring_ = MakeGate("worm.ring_diameter",
                   "max over time and rings of a ring's diameter difference, relative to the "
                   "reference's mid-body cross-section diameter",
                   0, gates.body_shape, "of the reference's mid-body diameter");
  membrane_gate_ =
      MakeGate("liquid.fraction_above_membrane",
               "max over time of the difference in the liquid fraction above the sheet", 0,
               gates.membrane_liquid_fraction, "of the liquid");
  if (membrane_) {
    liquid_ = GroupIndices(ref, "liquid");
    elastic_ = GroupIndices(ref, "elastic");
  }
  bond_ = MakeGate("elastic.bond_length",
                   "max over time and bonds (elastic pairs within 1.5 spacings at the reference's "
                   "first frame) of |length_cand - length_ref|, of the body's spacing",
                   NAN, gates.bond_length, "of the body's spacing");
  FindBonds(ref, ref_frames);
}

// Bonds: the elastic pairs within 1.5 times the body's spacing at the reference's frame 0.
void BodyGates::FindBonds(const Trajectory& ref, FrameSource& ref_frames) {
  bond_.detail = "the scene has no elastic body (under two particles)";
  if (ref.count(ParticleKind::kElastic) < 2 || ref.frame_count() == 0) return;
  const std::vector<std::size_t> elastic = GroupIndices(ref, "elastic");
  const FrameRef first = ref_frames.Frame(0);
  const double box = std::max(
      {ref.box.xmax - ref.box.xmin, ref.box.ymax - ref.box.ymin, ref.box.zmax - ref.box.zmin});
  bond_spacing_cu_ = MedianNearestSpacing(first, elastic, 0.01 * box, true);
  // The median particle's nearest lies within the spacing, so a spacing above 0 makes bonds.
  if (!(bond_spacing_cu_ > 0)) {
    bond_.detail =
        "no elastic body: its particles have no distinct nearest neighbour at the "
        "reference's first frame";
    return;
  }
  // At most 32 bonds a particle (Sibernetic's own cap on an elastic particle's connections; a
  // lattice has 18 within 1.5 spacings): a reference with its body's particles heaped together
  // would otherwise make bonds as the square of their number.
  constexpr unsigned char kNotElastic = 255, kMaxBonds = 32;
  std::vector<unsigned char> bonds_of(ref.particle_count(), kNotElastic);
  for (std::size_t i : elastic) bonds_of[i] = 0;
  ForEachPairWithin(first, elastic, 1.5 * bond_spacing_cu_,
                    [&](std::size_t a, std::size_t b, double) {
                      if (bonds_of[a] >= kMaxBonds || bonds_of[b] >= kMaxBonds) return;
                      ++bonds_of[a], ++bonds_of[b];
                      bonds_.push_back({a, b});
                    });
  if (!bonds_.empty()) bond_.value = 0;
}

void BodyGates::Observe(const FrameRef& ref, const FrameRef& cand, double box_scale_cu) {
  ObserveBonds(ref, cand);
  if (worm_) {
    const kinematics::BodyShape a = kinematics::MeasureBodyShape(ref.trajectory, ref.frame);
    const kinematics::BodyShape b = kinematics::MeasureBodyShape(cand.trajectory, cand.frame);
    const auto& p = a.centre_of_mass_cu;
    const auto& q = b.centre_of_mass_cu;
    const double distance = std::hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]) / box_scale_cu;
    com_.value = std::max(com_.value, std::isfinite(distance) ? distance : INFINITY);
    span_.value = std::max(span_.value, RelativeDifference(a.span_cu, b.span_cu));
    diameter_.value = std::max(diameter_.value, RelativeDifference(a.cross_section_diameter_cu,
                                                                   b.cross_section_diameter_cu));
    ObserveRings(a, b, ref.trajectory.time_s[ref.frame]);
  }
  if (membrane_) {
    last_reference_fraction_ = LiquidFractionAbove(ref, liquid_, elastic_);
    last_candidate_fraction_ = LiquidFractionAbove(cand, liquid_, elastic_);
    membrane_gate_.value = std::max(membrane_gate_.value,
                                    std::abs(last_reference_fraction_ - last_candidate_fraction_));
  }
}

namespace {
double Distance(const FrameRef& f, std::size_t a, std::size_t b) {
  const float* x = f.trajectory.position(f.frame, a);
  const float* y = f.trajectory.position(f.frame, b);
  return std::hypot(double(x[0]) - y[0], double(x[1]) - y[1], double(x[2]) - y[2]);
}
}  // namespace

void BodyGates::ObserveBonds(const FrameRef& ref, const FrameRef& cand) {
  for (std::size_t k = 0; k < bonds_.size(); ++k) {
    const auto [a, b] = bonds_[k];
    const double r = Distance(ref, a, b), c = Distance(cand, a, b);
    const double gap = std::abs(c - r) / bond_spacing_cu_;
    if (!(gap <= bond_.value)) {  // a NaN is kept: it fails
      bond_.value = std::isfinite(gap) ? gap : INFINITY;
      worst_bond_ = k;
      worst_bond_time_s_ = ref.trajectory.time_s[ref.frame];
      worst_bond_reference_cu_ = r;
      worst_bond_candidate_cu_ = c;
    }
  }
}

void BodyGates::ObserveRings(const kinematics::BodyShape& a, const kinematics::BodyShape& b,
                             double reference_time_s) {
  for (std::size_t k = 0; k < a.ring_diameter_cu.size(); ++k) {
    const double gap =
        std::abs(b.ring_diameter_cu[k] - a.ring_diameter_cu[k]) / a.cross_section_diameter_cu;
    if (!(gap <= ring_.value)) {  // a NaN is kept: it fails
      ring_.value = std::isfinite(gap) ? gap : INFINITY;
      worst_ring_bin_ = int(k) + kinematics::kFirstMidlineBin;
      worst_ring_time_s_ = reference_time_s;
      worst_ring_reference_cu_ = a.ring_diameter_cu[k];
      worst_ring_candidate_cu_ = b.ring_diameter_cu[k];
    }
  }
}

void BodyGates::AddGates(ParityReport* r) {
  if (worm_) {
    char detail[160];
    std::snprintf(detail, sizeof detail,
                  "worst ring: bin %d at %.6g s, %.4g cu (reference %.4g cu)", worst_ring_bin_,
                  worst_ring_time_s_, worst_ring_candidate_cu_, worst_ring_reference_cu_);
    ring_.detail = worst_ring_bin_ ? detail : "every ring's diameter equal";
  }
  if (worm_)
    for (Gate* g : {&com_, &span_, &diameter_, &ring_}) {
      Decide(g);
      r->gates.push_back(*g);
    }
  AddBondGate(r);
  if (membrane_) {
    membrane_gate_.detail = "at the last frame: reference " +
                            std::to_string(last_reference_fraction_) + ", candidate " +
                            std::to_string(last_candidate_fraction_);
    Decide(&membrane_gate_);
    r->gates.push_back(membrane_gate_);
  }
}

void BodyGates::AddBondGate(ParityReport* r) {
  if (bonds_.empty()) {  // n/a: FindBonds said why
    r->gates.push_back(bond_);
    return;
  }
  std::string worst = "every bond's length equal";
  if (bond_.value > 0) {
    char text[200];
    const auto [a, b] = bonds_[worst_bond_];
    std::snprintf(text, sizeof text,
                  "worst bond: particles %zu and %zu at %.6g s, %.4g cu (reference %.4g cu)", a, b,
                  worst_bond_time_s_, worst_bond_candidate_cu_, worst_bond_reference_cu_);
    worst = text;
  }
  char count[80];
  std::snprintf(count, sizeof count, "; %zu bonds, spacing %.4g cu", bonds_.size(),
                bond_spacing_cu_);
  bond_.detail = worst + count;
  Decide(&bond_);
  r->gates.push_back(bond_);
}

}  // namespace owval::compare::internal
