#include "worm_gates.hpp"

#include <algorithm>
#include <functional>
#include <memory>

#include "owval/base/errors.hpp"
#include "owval/engine/muscles.hpp"
#include "owval/kinematics/baseline.hpp"
#include "owval/kinematics/midline.hpp"
#include "owval/kinematics/muscle_log.hpp"
#include "owval/kinematics/side_files.hpp"
#include "owval/kinematics/worm_track.hpp"
#include "owval/trajectory/formats.hpp"
#include "owval/trajectory/frame_source.hpp"
#include "owval/trajectory/worm_formats.hpp"

namespace owval::ci::internal {
namespace fs = std::filesystem;
namespace {

// The directory's entries named *`extension`, sorted.
std::vector<fs::path> Entries(const fs::path& dir, const char* extension) {
  std::vector<fs::path> found;
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec))
    if (e.path().extension() == extension) found.push_back(e.path());
  std::sort(found.begin(), found.end());
  return found;
}

std::vector<fs::path> Wcons(const fs::path& dir) { return Entries(dir, ".wcon"); }

// A side file held to the candidate: `compare` measures the agreement; no candidate, or a file
// the comparison cannot read, fails the gate with the reason.
GateResult AgreementGate(const std::string& name, FrameSource* candidate,
                         const std::function<kinematics::TrackAgreement(FrameSource&)>& compare) {
  GateResult g{name, false, ""};
  try {
    if (!candidate) {
      g.detail = "no readable candidate trajectory to check it against";
      return g;
    }
    const kinematics::TrackAgreement a = compare(*candidate);
    g.pass = a.agrees;
    g.detail = a.detail;
  } catch (const std::exception& error) {
    g.detail = error.what();
  }
  return g;
}

GateResult ZarrGate(const fs::path& store, FrameSource* candidate) {
  return AgreementGate(store.filename().string() + " describes the candidate", candidate,
                       [&](FrameSource& frames) {
                         OmeZarrReader zarr(store);
                         return kinematics::CompareWithTrajectory(zarr, frames);
                       });
}

// A .wcon parsed once (quick-test's readability gate and its side-file gate both read it), or
// what the reader refused.
struct ParsedWcon {
  fs::path path;
  std::unique_ptr<WconReader> reader;
  std::string error;
};

ParsedWcon ParseWcon(const fs::path& path) {
  ParsedWcon wcon{path, nullptr, ""};
  try {
    wcon.reader = std::make_unique<WconReader>(path);
  } catch (const std::exception& error) {
    wcon.error = error.what();
  }
  return wcon;
}

// The file against the candidate read frame by frame in step with it (memory: one frame and
// one time point, whatever the run's length). `parsed`: the file's reader when quick-test has
// parsed it already, else null.
GateResult SideFileGate(const fs::path& file, FrameSource* candidate, ParsedWcon* parsed) {
  return AgreementGate(
      file.filename().string() + " describes the candidate", candidate, [&](FrameSource& frames) {
        if (parsed && !parsed->reader) throw InputError(parsed->error);
        return parsed ? kinematics::CompareWconWithTrajectory(*parsed->reader, frames)
               : file.extension() == ".wcon"
                   ? kinematics::CompareWconWithTrajectory(file, frames)
                   : kinematics::CompareWormMotionLogWithTrajectory(file, frames);
      });
}

// Sibernetic's muscle activations log against the signal owval computes for the candidate's
// logged steps (kinematics/muscle_log.hpp: line j is the activations after the step of frame j).
GateResult MuscleLogGate(const fs::path& file, FrameSource* candidate) {
  return AgreementGate(file.filename().string() + " holds owval's muscle signal", candidate,
                       [&](FrameSource& frames) {
                         return kinematics::CompareMuscleLogWithSignal(
                             file, frames.header(),
                             [](double step) { return engine::MuscleSimulationSignal(step); });
                       });
}

constexpr const char* kMuscleLogs[] = {"muscles_activity_buffer.txt",
                                       "muscles_activity_buffer.txt.gz"};

// Each .wcon, worm_motion_log.txt[.gz], muscles_activity_buffer.txt[.gz] and .zarr store in the
// directory against the candidate.
std::vector<GateResult> SideFileGates(const fs::path& dir, FrameSource* candidate,
                                      ParsedWcon* parsed) {
  std::vector<GateResult> gates;
  std::vector<fs::path> files = Wcons(dir);
  for (const char* log : {"worm_motion_log.txt", "worm_motion_log.txt.gz"})
    if (fs::exists(dir / log)) files.push_back(dir / log);
  for (const fs::path& f : files)
    gates.push_back(SideFileGate(f, candidate, parsed && parsed->path == f ? parsed : nullptr));
  for (const char* log : kMuscleLogs)
    if (fs::exists(dir / log)) gates.push_back(MuscleLogGate(dir / log, candidate));
  for (const fs::path& store : Entries(dir, ".zarr")) gates.push_back(ZarrGate(store, candidate));
  return gates;
}

// Read through time point by time point (memory: one), refusing what ReadWcon refuses.
GateResult WconReadable(ParsedWcon& wcon) {
  GateResult g{"worm run wrote a WCON", false, ""};
  try {
    if (!wcon.reader) throw InputError(wcon.error);
    WconReader& points = *wcon.reader;
    points.Rewind();
    WconTimePoint first, point;
    if (!points.Next(&first)) throw InputError(wcon.path.string(), 0, "data: no time point");
    while (points.Next(&point)) {
    }
    g.pass = true;
    g.detail = wcon.path.filename().string() + ": " + std::to_string(points.size()) +
               " time points, " + std::to_string(first.x_mm.size()) + " midline points";
  } catch (const std::exception& error) {
    g.detail = error.what();
  }
  return g;
}

// The side files' gates, the candidate opened once for them all (none when there is no side
// file); `parsed`: a .wcon already parsed, or null.
std::vector<GateResult> SideFileGatesOf(const fs::path& dir, const fs::path& candidate,
                                        ParsedWcon* parsed) {
  std::vector<GateResult> gates;
  const auto exists = [&](const char* name) { return fs::exists(dir / name); };
  if (Wcons(dir).empty() && Entries(dir, ".zarr").empty() && !exists("worm_motion_log.txt") &&
      !exists("worm_motion_log.txt.gz") && !exists(kMuscleLogs[0]) && !exists(kMuscleLogs[1]))
    return gates;  // nothing to hold to the candidate: skip opening it
  std::unique_ptr<FrameSource> frames;
  try {
    if (!candidate.empty()) {
      TextReadOptions quiet;
      quiet.quiet = true;
      frames = OpenFrameSource(candidate, quiet);
    }
  } catch (const std::exception&) {
    // The candidate's own gate says why it cannot be read; its side files stay unchecked.
  }
  return SideFileGates(dir, frames.get(), parsed);
}

}  // namespace

// The first .wcon is parsed once, for its readability gate and its side-file gate.
std::vector<GateResult> WormQuickTestGates(const fs::path& dir, const fs::path& candidate) {
  const std::vector<fs::path> wcons = Wcons(dir);
  if (wcons.empty()) {
    std::vector<GateResult> gates{
        {"worm run wrote a WCON", false,
         "no .wcon in " + dir.string() + " (DD001's quick test requires one for worm runs)"}};
    for (const GateResult& g : SideFileGatesOf(dir, candidate, nullptr)) gates.push_back(g);
    return gates;
  }
  ParsedWcon first = ParseWcon(wcons.front());
  std::vector<GateResult> gates{WconReadable(first)};
  for (const GateResult& g : SideFileGatesOf(dir, candidate, &first)) gates.push_back(g);
  return gates;
}

std::vector<GateResult> WormSideFileGates(const fs::path& dir, const fs::path& candidate) {
  return SideFileGatesOf(dir, candidate, nullptr);
}

std::vector<GateResult> WormValidateGates(const fs::path& dir,
                                          const kinematics::Analyser* reference,
                                          const kinematics::Analyser& candidate,
                                          FrameSource& candidate_frames) {
  std::vector<GateResult> gates = SideFileGates(dir, &candidate_frames, nullptr);
  const kinematics::Report cand = candidate.Finish();
  for (const kinematics::Tier3Check& c : kinematics::CheckTier3(cand))
    gates.push_back({"Tier-3 " + c.range.metric, c.pass, c.detail});
  if (reference) {
    const kinematics::Report ref = reference->Finish();
    for (const kinematics::AgreementCheck& c : kinematics::CompareKinematics(ref, cand))
      gates.push_back({"kinematics parity " + c.metric, c.pass, c.detail});
  }
  return gates;
}

}  // namespace owval::ci::internal
