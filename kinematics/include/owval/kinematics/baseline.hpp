#pragma once
// DD001's Tier-3 validation: a worm run's kinematics against the simulated baseline of Palyanov
// et al. 2018 (Phil. Trans. R. Soc. B 373:20170376, Table 1, as quoted in DD001): crawling
// 0.13-0.15 mm/s, 0.36-0.37 Hz, wavelength 0.62-0.72 mm; swimming 0.26-0.41 mm/s, 1.76-1.83 Hz,
// 0.43-0.47 mm. A metric passes when it lies in its range widened by the tolerance (15%: the
// range [low * 0.85, high * 1.15]). A metric that cannot be measured fails: a missing number
// is no evidence. The speed is signed (+ forward): Palyanov's worms go forward, so a backward
// speed fails whatever its magnitude.
#include <optional>
#include <string>
#include <vector>

#include "owval/kinematics/kinematics.hpp"

namespace owval::kinematics {

struct MetricRange {
  std::string metric;  // "speed", "frequency", "wavelength"
  std::string unit;    // "mm/s", "Hz", "mm"
  double low = 0, high = 0;
};

// The baseline of a regime (crawling or swimming); throws std::invalid_argument otherwise.
std::vector<MetricRange> PalyanovBaseline(Regime regime);

struct Tier3Check {
  MetricRange range;
  Regime regime = Regime::kUndetermined;
  std::optional<double> measured;  // signed midbody speed (+ forward), frequency, wavelength
  double tolerance = 0.15;
  bool pass = false;
  std::string detail;  // one line: value, range, tolerance band, or why it is missing
};

// Checks speed, frequency and wavelength against the regime's baseline. regime kUndetermined
// takes the report's own classification; when that is undetermined too every check fails.
std::vector<Tier3Check> CheckTier3(const Report& report, Regime regime = Regime::kUndetermined,
                                   double tolerance = 0.15);

// Two runs of the same scenario (two backends) agree when each metric differs by at most
// `tolerance` of the reference's value (issue 15: 5%); speeds signed, so opposite directions
// disagree. Missing in both = agreement.
struct AgreementCheck {
  std::string metric;
  std::optional<double> reference, candidate;
  bool pass = false;
  std::string detail;
};
std::vector<AgreementCheck> CompareKinematics(const Report& reference, const Report& candidate,
                                              double tolerance = 0.05);

}  // namespace owval::kinematics
