#include "body_gates.hpp"

#include <algorithm>
#include <cmath>

#include "owval/kinematics/body_shape.hpp"
#include "owval/kinematics/midline.hpp"

namespace owval::compare::internal {
namespace {

using Pairs = std::vector<std::pair<std::size_t, std::size_t>>;

double RelativeDifference(double reference, double candidate) {
  return std::abs(candidate / reference - 1);
}

void GateWorm(const Trajectory& ref, const Trajectory& cand, const Pairs& pairs,
              const ParityGates& gates, ParityReport* r) {
  Gate com = MakeGate("worm.centre_of_mass", "max over time of the worm's centre-of-mass distance",
                      0, gates.centroid_distance, "of the box");
  Gate span = MakeGate("worm.span", "max over time of the midline length's relative difference", 0,
                       gates.body_shape, "of the reference's");
  Gate diameter =
      MakeGate("worm.cross_section_diameter",
               "max over time of the mid-body cross-section diameter's relative difference", 0,
               gates.body_shape, "of the reference's");
  for (const auto& [fr, fc] : pairs) {
    const kinematics::BodyShape a = kinematics::MeasureBodyShape(ref, fr);
    const kinematics::BodyShape b = kinematics::MeasureBodyShape(cand, fc);
    const auto& p = a.centre_of_mass_cu;
    const auto& q = b.centre_of_mass_cu;
    const double distance = std::hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]) / r->box_scale_cu;
    com.value = std::max(com.value, std::isfinite(distance) ? distance : INFINITY);
    span.value = std::max(span.value, RelativeDifference(a.span_cu, b.span_cu));
    diameter.value = std::max(diameter.value, RelativeDifference(a.cross_section_diameter_cu,
                                                                 b.cross_section_diameter_cu));
  }
  for (Gate* g : {&com, &span, &diameter}) {
    Decide(g);
    r->gates.push_back(*g);
  }
}

// Every elastic particle within 1% of the box height of one plane, liquid present: a sheet.
bool IsMembraneScene(const Trajectory& t) {
  if (t.count(ParticleKind::kElastic) == 0 || t.count(ParticleKind::kLiquid) == 0 ||
      t.frame_count() == 0)
    return false;
  const std::vector<std::size_t> elastic = GroupIndices(t, "elastic");
  double lo = INFINITY, hi = -INFINITY;
  for (std::size_t i : elastic) {
    lo = std::min(lo, double(t.coordinate(0, i, 1)));
    hi = std::max(hi, double(t.coordinate(0, i, 1)));
  }
  return hi - lo < 0.01 * (t.box.ymax - t.box.ymin);
}

double LiquidFractionAbove(const Trajectory& t, std::size_t frame,
                           const std::vector<std::size_t>& liquid,
                           const std::vector<std::size_t>& elastic) {
  const double sheet_y = Centroid(t, frame, elastic)[1];
  std::size_t above = 0;
  for (std::size_t i : liquid) above += t.coordinate(frame, i, 1) > sheet_y;
  return double(above) / double(liquid.size());
}

void GateMembrane(const Trajectory& ref, const Trajectory& cand, const Pairs& pairs,
                  const ParityGates& gates, ParityReport* r) {
  const std::vector<std::size_t> liquid = GroupIndices(ref, "liquid");
  const std::vector<std::size_t> elastic = GroupIndices(ref, "elastic");
  Gate g = MakeGate("liquid.fraction_above_membrane",
                    "max over time of the difference in the liquid fraction above the sheet", 0,
                    gates.membrane_liquid_fraction, "of the liquid");
  double a = 0, b = 0;  // the fractions at the latest paired frame
  for (const auto& [fr, fc] : pairs) {
    a = LiquidFractionAbove(ref, fr, liquid, elastic);
    b = LiquidFractionAbove(cand, fc, liquid, elastic);
    g.value = std::max(g.value, std::abs(a - b));
  }
  g.detail =
      "at the last frame: reference " + std::to_string(a) + ", candidate " + std::to_string(b);
  Decide(&g);
  r->gates.push_back(g);
}

}  // namespace

void GateBodies(const Trajectory& ref, const Trajectory& cand, const Pairs& pairs,
                const ParityGates& gates, ParityReport* r) {
  if (kinematics::IsWorm(ref) && kinematics::IsWorm(cand)) GateWorm(ref, cand, pairs, gates, r);
  if (IsMembraneScene(ref)) GateMembrane(ref, cand, pairs, gates, r);
}

}  // namespace owval::compare::internal
