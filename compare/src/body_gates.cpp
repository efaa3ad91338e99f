#include "body_gates.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

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
}

void BodyGates::Observe(const FrameRef& ref, const FrameRef& cand, double box_scale_cu) {
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
  if (membrane_) {
    membrane_gate_.detail = "at the last frame: reference " +
                            std::to_string(last_reference_fraction_) + ", candidate " +
                            std::to_string(last_candidate_fraction_);
    Decide(&membrane_gate_);
    r->gates.push_back(membrane_gate_);
  }
}

}  // namespace owval::compare::internal
