#include "owval/kinematics/baseline.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace owval::kinematics {
namespace {

// The speed keeps its sign (+ forward, tail to head): Palyanov's speeds are of a worm going
// forward, and a worm going backwards at the reference's pace is not the reference's worm (its
// magnitude alone let the time-reversed reference pass the speed parity, 0.00% apart).
std::optional<double> Measured(const Report& r, const std::string& metric) {
  if (metric == "speed") return r.midbody_speed_mm_s;
  if (metric == "frequency") return r.frequency_hz;
  return r.wavelength_mm;
}

std::string Why(const Report& r, const std::string& metric) {
  if (metric == "speed")
    return "no speed: the run (" + std::to_string(r.duration_s) +
           " s) is shorter than the 0.5 s midbody window";
  if (metric == "frequency") return "no bend frequency: " + r.frequency_note;
  return "no wavelength: the body does not bend";
}

}  // namespace

std::vector<MetricRange> PalyanovBaseline(Regime regime) {
  if (regime == Regime::kCrawling)
    return {{"speed", "mm/s", 0.13, 0.15},
            {"frequency", "Hz", 0.36, 0.37},
            {"wavelength", "mm", 0.62, 0.72}};
  if (regime == Regime::kSwimming)
    return {{"speed", "mm/s", 0.26, 0.41},
            {"frequency", "Hz", 1.76, 1.83},
            {"wavelength", "mm", 0.43, 0.47}};
  throw std::invalid_argument("no baseline for an undetermined regime");
}

std::vector<Tier3Check> CheckTier3(const Report& report, Regime regime, double tolerance) {
  if (regime == Regime::kUndetermined) regime = report.regime;
  std::vector<Tier3Check> checks;
  if (regime == Regime::kUndetermined) {
    for (const char* m : {"speed", "frequency", "wavelength"}) {
      Tier3Check c{{m, "", 0, 0},
                   regime,
                   Measured(report, m),
                   tolerance,
                   false,
                   "regime undetermined (no bend frequency, no wavelength): no baseline"};
      checks.push_back(c);
    }
    return checks;
  }
  for (const MetricRange& range : PalyanovBaseline(regime)) {
    Tier3Check c{range, regime, Measured(report, range.metric), tolerance, false, ""};
    const double lo = range.low * (1 - tolerance), hi = range.high * (1 + tolerance);
    char buffer[256];
    if (c.measured) {
      c.pass = *c.measured >= lo && *c.measured <= hi;
      std::snprintf(
          buffer, sizeof buffer, "%.4g %s%s, baseline (%s) %.4g-%.4g %s, +-%.0f%%: %.4g-%.4g",
          *c.measured, range.unit.c_str(),
          range.metric == "speed" && *c.measured < 0 ? " (backwards)" : "", RegimeName(regime),
          range.low, range.high, range.unit.c_str(), tolerance * 100, lo, hi);
    } else {
      std::snprintf(buffer, sizeof buffer, "%s; baseline (%s) %.4g-%.4g %s",
                    Why(report, range.metric).c_str(), RegimeName(regime), range.low, range.high,
                    range.unit.c_str());
    }
    c.detail = buffer;
    checks.push_back(c);
  }
  return checks;
}

std::vector<AgreementCheck> CompareKinematics(const Report& ref, const Report& cand,
                                              double tolerance) {
  std::vector<AgreementCheck> checks;
  for (const char* m : {"speed", "frequency", "wavelength"}) {
    AgreementCheck c{m, Measured(ref, m), Measured(cand, m), false, ""};
    char buffer[200];
    if (c.reference && c.candidate) {
      const double gap =
          std::abs(*c.candidate - *c.reference) / std::max(std::abs(*c.reference), 1e-12);
      c.pass = gap <= tolerance;
      std::snprintf(buffer, sizeof buffer,
                    "reference %.4g, candidate %.4g: %.2f%% apart (max %.0f%%)", *c.reference,
                    *c.candidate, gap * 100, tolerance * 100);
    } else {
      c.pass = !c.reference && !c.candidate;
      std::snprintf(buffer, sizeof buffer, "reference %s, candidate %s",
                    c.reference ? "measured" : "none", c.candidate ? "measured" : "none");
    }
    c.detail = buffer;
    checks.push_back(c);
  }
  return checks;
}

}  // namespace owval::kinematics
