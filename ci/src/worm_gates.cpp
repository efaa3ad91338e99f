#include "worm_gates.hpp"

#include "owval/kinematics/baseline.hpp"
#include "owval/kinematics/midline.hpp"
#include "owval/trajectory/worm_formats.hpp"

namespace owval::ci::internal {
namespace fs = std::filesystem;

std::vector<GateResult> WormQuickTestGates(const fs::path& dir) {
  GateResult g{"worm run wrote a WCON", false, ""};
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) {
    if (e.path().extension() != ".wcon") continue;
    try {
      const WormTrack t = ReadWcon(e.path());
      g.pass = true;
      g.detail = e.path().filename().string() + ": " + std::to_string(t.time_s.size()) +
                 " time points, " + std::to_string(t.x_mm.front().size()) + " midline points";
      return {g};
    } catch (const std::exception& error) {
      g.detail = error.what();
      return {g};
    }
  }
  g.detail = "no .wcon in " + dir.string() + " (DD001's quick test requires one for worm runs)";
  return {g};
}

std::vector<GateResult> WormValidateGates(const kinematics::SkeletonSeries* reference,
                                          const kinematics::SkeletonSeries& candidate) {
  std::vector<GateResult> gates;
  const kinematics::Report cand = kinematics::Analyse(candidate);
  for (const kinematics::Tier3Check& c : kinematics::CheckTier3(cand))
    gates.push_back({"Tier-3 " + c.range.metric, c.pass, c.detail});
  if (reference) {
    const kinematics::Report ref = kinematics::Analyse(*reference);
    for (const kinematics::AgreementCheck& c : kinematics::CompareKinematics(ref, cand))
      gates.push_back({"kinematics parity " + c.metric, c.pass, c.detail});
  }
  return gates;
}

}  // namespace owval::ci::internal
