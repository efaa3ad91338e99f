#include "owval/ci/gates.hpp"

#include <memory>
#include <optional>
#include <sstream>

#include "caller_reference.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/input_file.hpp"
#include "owval/compare/stability.hpp"
#include "owval/kinematics/kinematics.hpp"
#include "owval/kinematics/midline.hpp"
#include "owval/kinematics/skeleton.hpp"
#include "owval/trajectory/formats.hpp"
#include "owval/trajectory/frame_source.hpp"
#include "worm_gates.hpp"

namespace owval::ci {
namespace fs = std::filesystem;
namespace {

// `file`: dir's run file `stem` as internal::RunFile resolved it ("" when there is none).
fs::path RequiredRunFile(const fs::path& file, const fs::path& dir, const std::string& stem) {
  if (!file.empty()) return file;
  throw InputError((dir / (stem + ".h5")).string(), 0,
                   "missing (expected " + stem + ".h5 or " + stem + ".txt)");
}

// Read frame by frame (issue 16): memory O(particles), whatever the number of frames.
std::unique_ptr<FrameSource> OpenRunFile(const fs::path& file) {
  TextReadOptions quiet;
  quiet.quiet = true;
  return OpenFrameSource(file, quiet);
}
std::unique_ptr<FrameSource> Open(const fs::path& dir, const std::string& stem) {
  return OpenRunFile(RequiredRunFile(internal::RunFile(dir, stem), dir, stem));
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

// quick-test's "completed without NaN": no non-finite position, and not a partial run (a run
// stopped on its first NaN leaves finite frames behind, and an interrupted one only finite ones).
void CompletedWithoutNaN(FrameSource& frames, GateResult* g) {
  const compare::StabilityReport s = compare::CheckStability(frames);
  g->pass = s.non_finite.count == 0 && !frames.partial();
  g->detail = std::to_string(frames.frame_count()) + " frames, " +
              std::to_string(s.non_finite.count) + " non-finite particle-frames";
  if (frames.partial()) g->detail += std::string("; ") + internal::kPartialRun;
}

// What validate measures on one trajectory, in one pass over its frames: stability, the
// incompressibility of its liquid (when asked, and it carries density and has liquid) and, for
// a worm, its kinematics (each frame's skeleton analysed as it is read, then dropped: the
// Analyser keeps 48 bytes a frame, where the whole skeleton series held ~1.6 kB).
struct TrajectoryChecks {
  compare::StabilityReport stability;
  std::optional<compare::IncompressibilityReport> incompressibility;
  std::optional<kinematics::Analyser> worm;
};

TrajectoryChecks Check(FrameSource& frames, bool incompressibility, bool worm) {
  frames.ReadFields();
  const Trajectory& header = frames.header();
  const std::size_t count = frames.frame_count();
  compare::StabilityMonitor stability(header.box, header.type);
  std::optional<compare::IncompressibilityMonitor> density;
  TrajectoryChecks c;
  if (worm) c.worm.emplace();
  for (std::size_t f = 0; f < count; ++f) {
    const FrameRef frame = frames.Frame(f);
    stability.Observe(frame);
    if (f == 0 && incompressibility && frame.trajectory.has_density() &&
        header.count(ParticleKind::kLiquid) > 0)
      density.emplace(header, count, true);
    if (density) density->Observe(f, frame);
    if (worm)
      c.worm->Observe(frame.trajectory.time_s[frame.frame],
                      kinematics::SkeletonAt(frame.trajectory, frame.frame));
  }
  c.stability = stability.report();
  if (count == 0) c.stability.velocities_from_positions = true;
  if (density) c.incompressibility = density->report();
  return c;
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

nlohmann::json GateReport::ToJson() const {
  nlohmann::json list = nlohmann::json::array();
  for (const GateResult& g : gates) {
    nlohmann::json gate = {{"name", g.name}, {"pass", g.pass}, {"detail", g.detail}};
    if (!g.measured.is_null()) gate["measured"] = g.measured;
    list.push_back(std::move(gate));
  }
  return {{"pass", pass()}, {"gates", list}};
}

GateReport QuickTest(const fs::path& dir) {
  RequireInputDirectory(dir, internal::kArtifactDirectory);
  // Both resolved before any gate: a directory holding two candidates is bad input (exit 2).
  const std::pair<const char*, fs::path> runs[] = {
      {"reference", internal::RunFile(dir, "reference")},
      {"candidate", internal::RunFile(dir, "candidate")}};
  GateReport r;
  bool worm = false;
  for (const auto& run : runs)  // not [stem, file]: clang before 16 cannot capture bindings
    r.gates.push_back(Run(std::string(run.first) + " completed without NaN", [&](GateResult* g) {
      const auto frames = OpenRunFile(RequiredRunFile(run.second, dir, run.first));
      worm = worm || kinematics::IsWorm(frames->header());
      CompletedWithoutNaN(*frames, g);
    }));
  if (worm) {
    // No candidate (""): its own gate above says so, and its side files stay unchecked.
    const fs::path& candidate = runs[1].second;
    for (const GateResult& g : internal::WormQuickTestGates(dir, candidate)) r.gates.push_back(g);
  }
  return r;
}

namespace {

// The directory's reference against the caller's, or a failed gate saying that none was given.
GateResult CallersReference(FrameSource& ref, FrameSource* wanted,
                            const fs::path& caller_reference) {
  return Run("reference is the caller's", [&](GateResult* g) {
    if (!wanted) {
      g->detail =
          "not checked: pass --reference FILE (the directory's reference could be its candidate "
          "under another name, and parity would judge the candidate against itself)";
      return;
    }
    const std::string why = internal::DifferenceFromCallersReference(ref, *wanted);
    g->pass = why.empty();
    g->detail = (why.empty() ? "the same as " : "NOT " + caller_reference.string() + ": ") +
                (why.empty() ? caller_reference.string() : why);
  });
}

}  // namespace

GateReport Validate(const fs::path& dir, const compare::ParityOptions& parity,
                    const fs::path& caller_reference) {
  RequireInputDirectory(dir, internal::kArtifactDirectory);
  GateReport r;
  const auto ref = Open(dir, "reference"), cand = Open(dir, "candidate");
  // An unreadable --reference is bad input (exit 2), not a failed gate.
  TextReadOptions quiet;
  quiet.quiet = true;
  const auto wanted = caller_reference.empty() ? nullptr : OpenFrameSource(caller_reference, quiet);
  r.gates.push_back(CallersReference(*ref, wanted.get(), caller_reference));
  const bool worm = kinematics::IsWorm(cand->header());
  const TrajectoryChecks ref_checks = Check(*ref, false, worm && kinematics::IsWorm(ref->header()));
  const TrajectoryChecks cand_checks = Check(*cand, true, worm);
  for (const auto* c : {&ref_checks, &cand_checks}) {
    const bool reference = c == &ref_checks;
    const std::string which = reference ? "reference" : "candidate";
    r.gates.push_back(Run(which + " stability", [&](GateResult* g) {
      g->pass = c->stability.pass();
      g->measured = c->stability.ToJson();
      g->detail = g->measured.dump();
    }));
    r.gates.push_back(Run(which + " completed", [&](GateResult* g) {
      g->pass = !(reference ? *ref : *cand).partial();
      g->detail = g->pass ? "not marked partial" : internal::kPartialRun;
    }));
  }
  if (cand_checks.incompressibility) {
    r.gates.push_back(Run("candidate incompressibility", [&](GateResult* g) {
      g->pass = cand_checks.incompressibility->pass();
      g->measured = cand_checks.incompressibility->ToJson();
      g->detail = g->measured.dump();
    }));
  }
  r.gates.push_back(Run("parity", [&](GateResult* g) {
    const compare::ParityReport p = compare::CompareFrameSources(*ref, *cand, parity);
    g->pass = p.pass();
    g->measured = {{"subject", p.subject},
                   {"paired_frames", p.frames.size()},
                   {"failing_frame_count", p.failing_frames.size()},
                   {"gates", compare::ToJson(p.gates)}};
    g->detail = p.subject + ": " + std::to_string(p.frames.size() - p.failing_frames.size()) + "/" +
                std::to_string(p.frames.size()) + " frames within the frame gate";
    if (!g->pass) g->detail += "; failed gates: " + p.FailedGates();
  }));
  if (worm)
    for (const GateResult& g : internal::WormValidateGates(
             dir, ref_checks.worm ? &*ref_checks.worm : nullptr, *cand_checks.worm, *cand))
      r.gates.push_back(g);
  return r;
}

}  // namespace owval::ci
