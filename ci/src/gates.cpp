#include "owval/ci/gates.hpp"

#include <sstream>

#include "owval/base/errors.hpp"
#include "owval/compare/stability.hpp"
#include "owval/kinematics/midline.hpp"
#include "owval/trajectory/formats.hpp"
#include "worm_gates.hpp"

namespace owval::ci {
namespace fs = std::filesystem;
namespace {

fs::path Find(const fs::path& dir, const std::string& stem) {
  for (const char* ext : {".h5", ".txt", ".txt.gz"})
    if (fs::exists(dir / (stem + ext))) return dir / (stem + ext);
  throw InputError((dir / (stem + ".h5")).string(), 0,
                   "missing (expected " + stem + ".h5 or " + stem + ".txt)");
}

Trajectory Load(const fs::path& dir, const std::string& stem) {
  TextReadOptions quiet;
  quiet.quiet = true;
  return ReadTrajectory(Find(dir, stem), quiet);
}

GateResult Run(const std::string& name, const std::function<void(GateResult*)>& body) {
  GateResult g{name, false, ""};
  try {
    body(&g);
  } catch (const std::exception& e) {
    g.pass = false;
    g.detail = e.what();
  }
  return g;
}

void NoNaN(const Trajectory& t, GateResult* g) {
  const compare::StabilityReport s = compare::CheckStability(t);
  g->pass = s.non_finite.count == 0;
  g->detail = std::to_string(t.frame_count()) + " frames, " + std::to_string(s.non_finite.count) +
              " non-finite particle-frames";
}

}  // namespace

bool GateReport::pass() const {
  for (const GateResult& g : gates)
    if (!g.pass) return false;
  return !gates.empty();
}

std::string GateReport::ToText() const {
  std::ostringstream s;
  for (const GateResult& g : gates)
    s << (g.pass ? "PASS " : "FAIL ") << g.name << ": " << g.detail << "\n";
  s << (pass() ? "all gates pass\n" : "a gate failed\n");
  return s.str();
}

GateReport QuickTest(const fs::path& dir) {
  GateReport r;
  bool worm = false;
  for (const char* stem : {"reference", "candidate"})
    r.gates.push_back(Run(std::string(stem) + " completed without NaN", [&](GateResult* g) {
      const Trajectory t = Load(dir, stem);
      worm = worm || kinematics::IsWorm(t);
      NoNaN(t, g);
    }));
  if (worm)
    for (const GateResult& g : internal::WormQuickTestGates(dir)) r.gates.push_back(g);
  return r;
}

GateReport Validate(const fs::path& dir, const compare::ParityOptions& parity) {
  GateReport r;
  const Trajectory ref = Load(dir, "reference"), cand = Load(dir, "candidate");
  for (const auto* t : {&ref, &cand}) {
    const std::string which = t == &ref ? "reference" : "candidate";
    r.gates.push_back(Run(which + " stability", [&](GateResult* g) {
      const compare::StabilityReport s = compare::CheckStability(*t);
      g->pass = s.pass();
      g->detail = s.ToJson().dump();
    }));
  }
  if (cand.has_density() && cand.count(ParticleKind::kLiquid) > 0) {
    r.gates.push_back(Run("candidate incompressibility", [&](GateResult* g) {
      const compare::IncompressibilityReport s = compare::CheckIncompressibility(cand);
      g->pass = s.pass();
      g->detail = s.ToJson().dump();
    }));
  }
  r.gates.push_back(Run("parity", [&](GateResult* g) {
    const compare::ParityReport p = compare::CompareTrajectories(ref, cand, parity);
    g->pass = p.pass();
    g->detail = p.subject + ": " + std::to_string(p.frames.size() - p.failing_frames.size()) + "/" +
                std::to_string(p.frames.size()) + " frames within the frame gate";
    if (!g->pass) g->detail += "; failed gates: " + p.FailedGates();
  }));
  if (kinematics::IsWorm(cand))
    for (const GateResult& g : internal::WormValidateGates(ref, cand)) r.gates.push_back(g);
  return r;
}

}  // namespace owval::ci
