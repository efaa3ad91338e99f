#include "owval/ci/checklist.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <exception>
#include <memory>
#include <optional>
#include <sstream>

#include "caller_reference.hpp"
#include "checklist_evidence.hpp"
#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/format.hpp"
#include "owval/base/input_file.hpp"
#include "owval/base/json_file.hpp"
#include "owval/base/one_line.hpp"
#include "owval/base/progress.hpp"
#include "owval/compare/signal_metrics.hpp"
#include "owval/kinematics/midline.hpp"
#include "owval/predict/predict.hpp"
#include "owval/render/read_back.hpp"
#include "owval/render/video_check.hpp"
#include "owval/trajectory/formats.hpp"
#include "owval/trajectory/frame_source.hpp"
#include "owval/trajectory/track.hpp"
#include "worm_gates.hpp"

namespace owval::ci {
namespace fs = std::filesystem;
namespace {
using internal::Check;
using internal::CheckFitHistory;
using internal::Evidence;
using internal::FitHistory;

std::unique_ptr<FrameSource> Open(const fs::path& file) {
  TextReadOptions quiet;
  quiet.quiet = true;
  return OpenFrameSource(file, quiet);
}

std::unique_ptr<FrameSource> TryOpen(const fs::path& file) {
  if (file.empty()) return nullptr;
  try {
    return Open(file);
  } catch (const std::exception&) {
    return nullptr;  // the item's own check opens it again and reports why
  }
}

FrameSource& Need(const std::unique_ptr<FrameSource>& t, const char* which) {
  if (!t) throw InputError(std::string("the ") + which + " trajectory is missing or unreadable");
  return *t;
}

predict::Prediction ReadPrediction(const fs::path& path) {
  return predict::Prediction::FromJson(ReadJsonFile(path), path.string());
}

void CheckPrediction(Evidence& e, ChecklistItem* item) {
  const predict::Prediction p = ReadPrediction(e.dir / "prediction.json");
  item->detail = std::to_string(p.predictions.size()) + " predicted quantities";
  if (e.options.git_range.empty()) {
    item->pass = true;
    item->detail +=
        "; written before the run: NOT CHECKED (a plain directory has no order; pass "
        "--git-range BASE..HEAD)";
    return;
  }
  std::string order;
  item->pass = PredictionCommittedFirst(e.dir, e.options.git_range, &order);
  item->detail += "; " + order;
}

// Every frame read and its positions checked. A frame that cannot be read makes the trajectory
// unreadable for the later items (`source` reset), as a failed whole read did.
void CheckTrajectory(const fs::path& file, std::unique_ptr<FrameSource>& source,
                     ChecklistItem* item) {
  FrameSource& t = source ? *source : *(source = Open(file));
  const std::size_t values = 3 * t.particle_count();
  bool finite = true;
  try {
    for (std::size_t f = 0; f < t.frame_count() && finite; ++f) {
      const FrameRef frame = t.Frame(f);
      const float* x = frame.trajectory.position(frame.frame, 0);
      finite = std::all_of(x, x + values, [](float v) { return std::isfinite(v); });
    }
  } catch (const std::exception&) {
    source.reset();
    throw;
  }
  if (!finite) throw InputError(file.string(), 0, "contains NaN or Inf positions");
  item->detail = file.filename().string() + ": " + std::to_string(t.frame_count()) + " frames, " +
                 std::to_string(t.particle_count()) + " particles";
  item->pass = t.frame_count() >= 2;
  if (!item->pass) item->detail += " (expected at least 2 frames)";
  // An interrupted or blown-up run (owval writes it under a .partial name, with HDF5 attribute
  // partial = 1) is not a result: compared over the frames it has, one stopped in the last 2% of
  // the reference's duration passed the window gate, and the checklist said ready.
  if (t.partial()) {
    item->pass = false;
    item->detail += std::string(" (") + internal::kPartialRun + ")";
  }
}

// Why an owval run may not stand as the reference, or empty: its provenance says it is not
// reference-equivalent (another scheme, or constants changed; a candidate copied over the
// reference). Sibernetic's own files carry no such record.
std::string NotReferenceEquivalent(const Trajectory& header) {
  const auto& provenance = header.provenance;
  const auto equivalent = provenance.find("reference_equivalent");
  if (equivalent == provenance.end() || equivalent->second == "true") return "";
  const auto producer = provenance.find("producer"), constants = provenance.find("constants");
  return "made by " + (producer != provenance.end() ? producer->second : "owval") +
         ", not reference-equivalent" +
         (constants != provenance.end() ? " (constants: " + constants->second + ")" : "");
}

void CheckReference(Evidence& e, ChecklistItem* item) {
  CheckTrajectory(e.reference_file, e.reference, item);
  if (!e.caller_reference) {
    // The directory's own reference file could be its candidate under another name: without a
    // reference from the caller, the parity gate would judge the candidate against itself.
    item->pass = false;
    const std::string why = NotReferenceEquivalent(e.reference->header());
    item->detail +=
        "; not checked against a reference of the caller's: pass --scenario NAME or "
        "--reference FILE" +
        (why.empty() ? std::string() : " (and its own record says: " + why + ")");
    return;
  }
  if (!item->pass) return;
  const std::string why =
      internal::DifferenceFromCallersReference(*e.reference, *e.caller_reference);
  item->pass = why.empty();
  item->detail +=
      why.empty()
          ? "; the caller's reference (" + e.options.caller_reference_source + ")"
          : "; NOT the caller's reference (" + e.options.caller_reference_source + "): " + why;
}
// A worm candidate's side files (WCON, midline log, Zarr store: what other tools read) must
// describe it, as in `owval ci quick-test`: a frozen worm beside the reference's WCON was ready.
void CheckCandidate(Evidence& e, ChecklistItem* item) {
  const fs::path& file = e.candidate_file;
  CheckTrajectory(file, e.candidate, item);
  if (!kinematics::IsWorm(e.candidate->header())) return;
  const std::vector<GateResult> side_files = internal::WormSideFileGates(e.dir, file);
  std::size_t agree = 0;
  for (const GateResult& g : side_files) {
    if (g.pass) {
      ++agree;
      continue;
    }
    item->pass = false;
    item->detail += "; FAILS " + g.name + ": " + g.detail;
  }
  if (agree > 0) item->detail += "; " + std::to_string(agree) + " worm side file(s) describe it";
}

// The video's decoded frame count against the runs it claims to show: `owval render sxs` draws
// one frame per paired frame (evenly sampled down to --max-frames), so a video of the two runs
// has at least two frames (one frame is a still) and no more than the runs have paired frames
// (more is some other video). Without both trajectories there is nothing to hold it to.
bool VideoFramesFitTheRuns(const Evidence& e, const render::VideoInfo& v, std::string* detail) {
  if (!e.reference || !e.candidate) return true;
  const std::size_t paired = PairFramesByTime(e.reference->header(), e.candidate->header()).size();
  if (paired < 2) return true;
  if (v.decoded_frames >= 2 && v.decoded_frames <= paired) return true;
  *detail += " (expected 2 to " + std::to_string(paired) +
             " frames: the runs' paired frames, one video frame each at most)";
  return false;
}

// The video decoded, and with both runs its pixels held to them: its frames drawn again with the
// options its render record names (render/video_check.hpp), in the same pass. Codec, shape and
// frame count say nothing of what it shows: a video of the reference twice, or of another
// scenario, passed them.
void CheckVideo(Evidence& e, ChecklistItem* item) {
  const fs::path mp4 = e.dir / "sxs.mp4";
  std::optional<render::SideBySideCheck> shows;
  if (e.reference && e.candidate) {
    render::SideBySideCheckOptions options;
    options.quiet = QuietMode();
    shows = render::CheckSideBySide(mp4, *e.reference, *e.candidate, options);
  }
  const render::VideoInfo v = shows ? shows->video : render::ProbeVideo(mp4);
  std::ostringstream s;
  s << v.codec << " " << v.width << "x" << v.height << ", " << v.decoded_frames
    << " frames decoded, " << v.duration_s << " s";
  // Two panels side by side: at least 1.5 times as wide as high.
  const bool two_panels = v.height > 0 && double(v.width) / v.height >= 1.5;
  if (!two_panels) s << " (not two panels wide: width/height < 1.5)";
  if (v.codec != "h264") s << " (expected h264)";
  item->detail = s.str();
  item->pass = two_panels && v.codec == "h264" && VideoFramesFitTheRuns(e, v, &item->detail);
  if (item->pass && shows) {
    item->pass = shows->pass;
    item->detail += "; " + shows->detail;
  }
}

std::size_t DecodedPngs(const fs::path& frames_dir) {
  std::size_t pngs = 0;
  if (fs::is_directory(frames_dir))
    for (const auto& entry : fs::directory_iterator(frames_dir))
      if (entry.path().extension() == ".png") {
        render::ProbePng(entry.path());
        ++pngs;
      }
  return pngs;
}

// The entries of frames.json whose "image" is not a PNG file in frames/ (by its name).
std::vector<std::string> MissingImages(const nlohmann::json& entries, const fs::path& frames_dir) {
  std::vector<std::string> missing;
  for (const auto& f : entries) {
    const nlohmann::json none;
    const nlohmann::json& image = f.is_object() && f.contains("image") ? f["image"] : none;
    const std::string name = image.is_string() ? image.get<std::string>() : "";
    const bool plain = !name.empty() && fs::path(name).filename() == name;
    if (!plain || !fs::is_regular_file(frames_dir / name))
      missing.push_back(name.empty() ? "(no image)" : name);
  }
  return missing;
}

// The labelled values of frames.json against the trajectories: returns how many agree.
std::size_t AgreeingLabels(const nlohmann::json& entries, const Track& track, FrameSource& ref,
                           FrameSource& cand, std::vector<std::size_t>* reference_frames) {
  auto agrees = [&](FrameSource& t, const nlohmann::json& frame, const nlohmann::json& value) {
    if (!frame.is_number_unsigned() || !value.is_number()) return false;
    const std::size_t f = frame.get<std::size_t>();
    // Past the end: ValueAt's own error, from the header (which knows the frame count).
    if (f >= t.frame_count()) track.ValueAt(t.header(), f);
    const FrameRef x = t.Frame(f);
    const double actual = track.ValueAt(x.trajectory, x.frame);
    return std::abs(actual - value.get<double>()) <= 1e-3 * std::max(1.0, std::abs(actual));
  };
  std::size_t agree = 0;
  for (const auto& f : entries) {
    if (!f.is_object()) continue;
    const nlohmann::json none;
    const auto& rf = f.contains("reference_frame") ? f["reference_frame"] : none;
    agree += agrees(ref, rf, f.value("reference_value", none)) &&
             agrees(cand, f.value("candidate_frame", none), f.value("candidate_value", none));
    if (rf.is_number_unsigned()) reference_frames->push_back(rf.get<std::size_t>());
  }
  return agree;
}

// frames/frames.json: an object with a "frames" list, labelled with the track the checklist
// follows (the caller's, never the file's).
nlohmann::json ReadLabelledFrames(const Evidence& e) {
  const fs::path json_path = e.dir / "frames" / "frames.json";
  nlohmann::json j = ReadJsonFile(json_path);
  if (!j.is_object() || !j.contains("frames") || !j["frames"].is_array())
    throw InputError(json_path.string(), 0, "expected an object with a \"frames\" list");
  const Track& track = e.track;
  const Track labelled =
      Track::FromJson(j.value("track", nlohmann::json::object()), json_path.string());
  if (labelled.Describe() != track.Describe())
    throw InputError(json_path.string(), 0,
                     "labels " + labelled.Describe() + ", but the checklist tracks " +
                         track.Describe() + " (" + e.track_source + ")");
  return j;
}

// The frame gate at the sampled frames, as `owval compare --frames` computes it, and the group
// centroids' gate there when the report has one: each adds its worst value to the item's detail
// and fails the item when it fails.
void JudgeSampledFrames(const Evidence& e, FrameSource& ref, FrameSource& cand,
                        const std::vector<std::size_t>& sampled, ChecklistItem* item) {
  const Track& track = e.track;
  const compare::SampledFrameParity p =
      compare::CompareSampledFrames(ref, cand, {track, sampled, std::nullopt, e.options.gates});
  const compare::Gate& gate = p.frames;
  item->detail += "; " + track.Describe() + " |delta| at the sampled frames: worst " +
                  FormatPercent(gate.value) + " of the reference range (gate < " +
                  FormatPercent(gate.threshold.value) + ")";
  if (gate.status == compare::GateStatus::kFail) {
    item->pass = false;
    item->detail += ", FAILS at frames";
    // Appended piece by piece: `" " + std::to_string(f)` inlined here trips GCC 12's -Wrestrict
    // false positive (GCC bug 105329).
    for (std::size_t f : p.failing_frames) item->detail.append(" ").append(std::to_string(f));
  }
  if (const std::optional<compare::Gate>& groups = p.group_centroids) {
    item->detail += "; group centroids at the sampled frames: worst " +
                    FormatPercent(groups->value) + " of the box (gate < " +
                    FormatPercent(groups->threshold.value) + ")";
    if (groups->status == compare::GateStatus::kFail) {
      item->pass = false;
      item->detail += ", FAILS: " + groups->detail;
    }
  }
}

void CheckFrames(Evidence& e, ChecklistItem* item) {
  const std::size_t pngs = DecodedPngs(e.dir / "frames");
  const nlohmann::json j = ReadLabelledFrames(e);
  FrameSource& ref = Need(e.reference, "reference");
  FrameSource& cand = Need(e.candidate, "candidate");
  std::vector<std::size_t> sampled;
  const std::size_t agree = AgreeingLabels(j["frames"], e.track, ref, cand, &sampled);
  const std::size_t listed = j["frames"].size();
  item->detail = std::to_string(pngs) + " PNGs decode; " + std::to_string(agree) + "/" +
                 std::to_string(listed) + " labelled values agree with the trajectories";
  item->pass = pngs >= 3 && listed >= 3 && agree == listed;
  const std::vector<std::string> missing = MissingImages(j["frames"], e.dir / "frames");
  if (!missing.empty()) {
    item->pass = false;
    item->detail += "; " + std::to_string(missing.size()) + " listed images missing (" +
                    missing.front() + (missing.size() > 1 ? ", ..." : "") + ")";
  }
  if (sampled.empty()) return;
  JudgeSampledFrames(e, ref, cand, sampled, item);
}

// A test's "pass" is a claim; its own "relative_error" against its own "tolerance" (every
// fd_tests.json test has both: docs/schemas/fd_tests.schema.json) is the evidence. A test that
// says pass with an error beyond its tolerance, a non-finite one or none at all is counted as
// failing, by name.
bool TestPasses(const nlohmann::json& t, std::string* contradicted) {
  if (!t.is_object() || !t.value("pass", false)) return false;
  const nlohmann::json none;
  const nlohmann::json& error = t.contains("relative_error") ? t["relative_error"] : none;
  const nlohmann::json& tolerance = t.contains("tolerance") ? t["tolerance"] : none;
  const bool holds = error.is_number() && tolerance.is_number() &&
                     std::isfinite(error.get<double>()) &&
                     error.get<double>() <= tolerance.get<double>();
  if (holds || !contradicted->empty()) return holds;
  const std::string name = t.contains("name") && t["name"].is_string()
                               ? t["name"].get<std::string>()
                               : std::string("a test");
  *contradicted = error.is_null() || tolerance.is_null()
                      ? name + " says pass, but gives no relative_error and tolerance"
                      : name + " says pass, but its relative_error " + error.dump() +
                            " is not within its tolerance " + tolerance.dump();
  return holds;
}

void CheckFdTests(Evidence& e, ChecklistItem* item) {
  const fs::path path = e.dir / "fd_tests.json";
  const nlohmann::json j = ReadJsonFile(path);
  if (!j.is_object() || !j.contains("tests") || !j["tests"].is_array())
    throw InputError(path.string(), 0, "expected an object with a \"tests\" list");
  std::size_t passed = 0, total = 0;
  std::string contradicted;
  for (const auto& t : j["tests"]) {
    ++total;
    passed += TestPasses(t, &contradicted);
  }
  item->detail =
      std::to_string(passed) + "/" + std::to_string(total) + " finite-difference tests pass";
  if (!contradicted.empty()) item->detail += " (" + contradicted + ")";
  item->pass = total > 0 && passed == total;
}

// The tuned values against the fit that claims them: each of fit/history.json's best
// parameters ("final") must be in parameters.json with its value, to 6 significant digits (a
// value copied from a printout). "" when they agree, or when there is no readable history to
// hold them to (item 6 reports that); else the first disagreement. Values the fit did not tune
// may stand beside them.
std::string DisagreementWithFit(Evidence& e, const nlohmann::json& values) {
  const nlohmann::json* history_read = nullptr;
  try {
    history_read = &FitHistory(e);
  } catch (const InputError&) {
    return "";
  }
  const nlohmann::json& history = *history_read;
  const nlohmann::json none;
  const nlohmann::json& final = history.contains("final") ? history["final"] : none;
  if (!final.is_object() || !final.contains("parameters") || !final["parameters"].is_object())
    return "";
  for (const auto& [name, best] : final["parameters"].items()) {
    if (!best.is_number()) continue;
    if (!values.contains(name)) return "lacks the fit's " + name;
    const nlohmann::json& given = values[name];
    const double b = best.get<double>();
    if (!given.is_number() || !(std::abs(given.get<double>() - b) <= 5e-6 * std::abs(b)))
      return name + " is " + OneLine(given.dump(), 40) + ", the fit's best (fit/history.json) " +
             FormatNumber(b, 6);
  }
  return "";
}

void CheckParameters(Evidence& e, ChecklistItem* item) {
  const nlohmann::json j = ReadJsonFile(e.dir / "parameters.json");
  const nlohmann::json values = j.is_object() && j.contains("parameters") ? j["parameters"] : j;
  item->detail = std::to_string(values.size()) + " tuned values";
  item->pass = values.is_object() && !values.empty();
  if (!item->pass) return;
  const std::string disagreement = DisagreementWithFit(e, values);
  item->pass = disagreement.empty();
  if (!item->pass) item->detail += "; parameters.json " + disagreement;
}

// A Markdown list item: optional indentation, then "-", "*", "+" or "1." and a space, then text.
bool IsListItem(const std::string& line) {
  std::size_t i = line.find_first_not_of(" \t");
  if (i == std::string::npos) return false;
  if (line[i] == '-' || line[i] == '*' || line[i] == '+') {
    ++i;
  } else {
    const std::size_t digits = line.find_first_not_of("0123456789", i);
    if (digits == i || digits == std::string::npos || line[digits] != '.') return false;
    i = digits + 1;
  }
  if (i >= line.size() || (line[i] != ' ' && line[i] != '\t')) return false;
  return line.find_first_not_of(" \t", i) != std::string::npos;
}

void CheckChanges(Evidence& e, ChecklistItem* item) {
  std::istringstream in(ReadWholeFile(e.dir / "changes.md"));
  std::size_t items = 0;
  for (std::string line; std::getline(in, line);) items += IsListItem(line);
  item->detail = std::to_string(items) + " itemised changes";
  item->pass = items > 0;
}

// DD001: the prediction is reconciled with the reference measurement (the validated physics),
// recomputed here from prediction.json and the reference trajectory.
// With a scenario: the scenario's tolerance for each of its gated quantities, which
// prediction.json must hold, with the scenario's track. InputError naming what differs.
predict::ReconcileOptions ScenarioTolerances(const predict::Prediction& file,
                                             const predict::Prediction& scenario) {
  if (file.track.Describe() != scenario.track.Describe())
    throw InputError("prediction.json", 0,
                     "tracks " + file.track.Describe() + ", the scenario's prediction " +
                         scenario.track.Describe());
  predict::ReconcileOptions o;
  for (const predict::PredictedQuantity& q : scenario.predictions) {
    if (q.tolerance <= 0) continue;  // informative
    if (!file.Find(q.quantity))
      throw InputError("prediction.json", 0,
                       "lacks " + q.quantity + ", which the scenario's predictor gates");
    o.tolerances[q.quantity] = q.tolerance;
  }
  return o;
}

void CheckReconcile(Evidence& e, ChecklistItem* item) {
  const predict::Prediction prediction = ReadPrediction(e.dir / "prediction.json");
  const predict::ReconcileOptions tolerances =
      e.options.scenario_prediction ? ScenarioTolerances(prediction, *e.options.scenario_prediction)
                                    : predict::ReconcileOptions{};
  const predict::Reconciliation r =
      predict::Reconcile(prediction, Need(e.reference, "reference"), tolerances);
  item->pass = r.pass;
  std::string failing;
  for (const predict::ReconcileRow& row : r.rows)
    if (row.pass == false) failing += (failing.empty() ? "" : ", ") + row.quantity;
  item->detail = "prediction reconciled with the reference's measurement: " +
                 (item->pass ? std::string("every gap within tolerance")
                             : "gap beyond tolerance in " + failing) +
                 (e.options.scenario_prediction ? " (the scenario's tolerances)"
                                                : " (prediction.json's tolerances: pass --scenario "
                                                  "for the scenario's)");
}

struct ItemSpec {
  int number;
  const char* title;
  std::vector<const char*> files;  // any of these present counts as present
  Check check;
};

const std::vector<ItemSpec>& Items() {
  static const std::vector<ItemSpec> items = {
      {1, "prediction written before the run", {"prediction.json"}, CheckPrediction},
      {2, "reference trajectory", {"reference.h5", "reference.txt"}, CheckReference},
      {3, "candidate trajectory", {"candidate.h5", "candidate.txt"}, CheckCandidate},
      {4, "side-by-side MP4 (reference left)", {"sxs.mp4"}, CheckVideo},
      {5, ">= 3 labelled frame PNGs within the frame gate", {"frames/frames.json"}, CheckFrames},
      {6, "fit convergence history", {"fit/history.json"}, CheckFitHistory},
      {7, "finite-difference tests for new kernels", {"fd_tests.json"}, CheckFdTests},
      {8, "tuned parameter values", {"parameters.json"}, CheckParameters},
      {9, "itemised substrate changes", {"changes.md"}, CheckChanges},
      {10,
       "prediction reconciled with the reference measurement",
       {"prediction.json"},
       CheckReconcile},
  };
  return items;
}

ChecklistItem Evaluate(Evidence& e, const ItemSpec& spec) {
  ChecklistItem item;
  item.number = spec.number;
  item.title = spec.title;
  item.present = std::any_of(spec.files.begin(), spec.files.end(),
                             [&](const char* f) { return fs::exists(e.dir / f); });
  if (!item.present) {
    item.detail = std::string("missing: ") + spec.files.front();
    return item;
  }
  try {
    spec.check(e, &item);
  } catch (const EnvironmentError&) {
    throw;  // the machine's failure (no OSMesa), not the item's: exit 3
  } catch (const std::exception& ex) {
    item.pass = false;
    item.detail = ex.what();
  }
  return item;
}

// The parity gate, recomputed from the trajectories; a parity.json that disagrees is stale.
// A quantity that does not move in the reference agrees with any candidate that leaves it
// alone (a wall particle, scale 1 cu): its frame gate is no evidence.
void CheckTrackedMotion(ChecklistReport* r) {
  const compare::SignalMetrics& reference = r->parity->reference_metrics;  // over the common window
  r->tracked_moves = reference.maximum > reference.minimum;
  if (!r->tracked_moves)
    r->parity_note = r->parity->subject +
                     " does not move in the reference: its frame gate is no evidence (track a "
                     "quantity that moves, e.g. with --scenario)";
}

// Not a gate: a candidate equal to the reference at every paired frame, particle for particle, is
// either a perfect port or a copy of the reference, and the trajectories cannot tell which.
// owval's PCISPH is byte-identical to Sibernetic's runs by design (docs/parity.md); a port to
// another substrate is not expected to be (its floating-point order differs). The reviewer is
// told, with the candidate's own record of what made it (forgeable: a claim, not evidence).
std::string IdenticalCandidateNote(const compare::ParityReport& p, const Trajectory& candidate) {
  for (const compare::Gate& g : p.gates) {
    const bool distance = g.name == "initial_state" || g.name.ends_with(".worst_particle");
    if (distance && g.value != 0) return "";
  }
  const auto producer = candidate.provenance.find("producer");
  return "the candidate equals the reference at every paired frame, particle for particle: a "
         "perfect port (owval's PCISPH is, by design) or a copy of the reference, which the "
         "files cannot tell apart; the candidate's own record says: " +
         (producer != candidate.provenance.end() ? "producer " + producer->second
                                                 : std::string("no producer (none recorded)"));
}

// The caller's gates looser than DD001's defaults: a candidate that passes them is compared
// again with those put back to the defaults, and the gates it fails there are recorded (the
// parity gate then fails: "ready" is never said of a candidate that passes only loosened gates).
void JudgeLoosenedGates(Evidence& e, ChecklistReport* r) {
  r->loosened_thresholds = compare::LoosenedThresholds(e.options.gates);
  if (r->loosened_thresholds.empty() || !r->parity->pass()) return;
  const compare::ParityReport strict = compare::CompareFrameSources(
      *e.reference, *e.candidate,
      {e.track, {}, std::nullopt, compare::NoLooserThanDefaults(e.options.gates)});
  if (!strict.pass()) r->failed_at_default_thresholds = strict.FailedGates();
}

void JudgeParity(Evidence& e, ChecklistReport* r) {
  if (!e.reference || !e.candidate) return;
  try {
    r->parity = compare::CompareFrameSources(*e.reference, *e.candidate,
                                             {e.track, {}, std::nullopt, e.options.gates});
    JudgeLoosenedGates(e, r);
  } catch (const std::exception& ex) {
    r->parity_note = std::string("parity could not be computed: ") + ex.what();
    return;
  }
  CheckTrackedMotion(r);
  r->candidate_note = IdenticalCandidateNote(*r->parity, e.candidate->header());
  if (!r->tracked_moves) return;
  const fs::path stored = e.dir / "parity.json";
  if (!fs::exists(stored)) return;
  try {
    const nlohmann::json j = ReadJsonFile(stored);
    const bool says_pass = j.is_object() && j.value("pass", false);
    if (says_pass != r->parity->pass())
      r->parity_note = std::string("parity.json is stale: it says ") +
                       (says_pass ? "pass" : "FAIL") + ", recomputed " +
                       (r->parity->pass() ? "pass" : "FAIL");
  } catch (const std::exception& ex) {
    r->parity_note = std::string("parity.json ignored: ") + ex.what();
  }
}

std::string LoosenedList(const ChecklistReport& r) {
  std::string list;
  for (const std::string& l : r.loosened_thresholds) list += (list.empty() ? "" : ", ") + l;
  return list;
}

std::string ParityBlocking(const ChecklistReport& r) {
  if (!r.parity || !r.tracked_moves) return "parity gate (" + r.parity_note + ")";
  if (!r.parity->pass()) return "parity gate (failed: " + r.parity->FailedGates() + ")";
  return "parity gate (passes only with thresholds looser than DD001's defaults: " +
         LoosenedList(r) + "; at the defaults it fails: " + r.failed_at_default_thresholds + ")";
}

void Decide(ChecklistReport* r) {
  auto fails = [&](int n) { return !r->items[std::size_t(n - 1)].pass; };
  auto block = [&](int n) {
    const ChecklistItem& i = r->items[std::size_t(n - 1)];
    r->blocking.push_back("item " + std::to_string(n) + " (" + i.title + ")");
  };
  for (int n : {2, 3, 1, 4, 5, 6})
    if (fails(n)) block(n);
  if (!fails(2) && !fails(3) && !r->parity_pass()) r->blocking.push_back(ParityBlocking(*r));
  if (fails(2) || fails(3)) {
    r->verdict = Verdict::kUnreviewable;
  } else if (!r->blocking.empty()) {
    r->verdict = Verdict::kNotReady;
  } else {
    for (int n : {7, 8, 9, 10})
      if (fails(n)) block(n);
    r->verdict = r->blocking.empty() ? Verdict::kReady : Verdict::kIncomplete;
  }
}

}  // namespace

const char* VerdictName(Verdict v) {
  switch (v) {
    case Verdict::kReady:
      return "ready";
    case Verdict::kIncomplete:
      return "incomplete but not blocking";
    case Verdict::kNotReady:
      return "not ready";
    case Verdict::kUnreviewable:
      return "unreviewable";
  }
  return "?";
}

int ChecklistReport::exit_code() const {
  return verdict == Verdict::kReady || verdict == Verdict::kIncomplete ? 0 : 1;
}

std::vector<fs::path> EvidenceFiles(const fs::path& directory) {
  std::vector<fs::path> files;
  std::error_code error;
  for (fs::recursive_directory_iterator it(directory, error), end; !error && it != end;
       it.increment(error)) {
    if (it->is_regular_file(error)) files.push_back(it->path());
    if (files.size() >= 10000) break;
  }
  return files;
}

// ChecklistReport::loosened_fit_rerun: the caller's item-6 tolerance when looser than DD001's,
// and what the rerun gave at the default.
std::string LoosenedFitRerun(const Evidence& e) {
  const double given = e.options.fit_rerun_tolerance,
               default_value = ChecklistOptions{}.fit_rerun_tolerance;
  if (given <= default_value) return "";
  return "fit_rerun_tolerance " + FormatNumber(given) + " (caller; default " +
         FormatNumber(default_value) + "): " +
         (e.rerun_at_default_tolerance.empty() ? std::string("item 6 made no rerun")
                                               : e.rerun_at_default_tolerance);
}

ChecklistReport RunChecklist(const fs::path& directory, const ChecklistOptions& options) {
  RequireInputDirectory(directory, internal::kArtifactDirectory);
  if (!options.git_range.empty()) CheckGitRange(directory, options.git_range);  // a bad flag: 2
  const fs::path reference_file = internal::RunFile(directory, "reference"),
                 candidate_file = internal::RunFile(directory, "candidate");
  Evidence e{directory,
             options,
             reference_file,
             candidate_file,
             TryOpen(reference_file),
             TryOpen(candidate_file),
             options.track.value_or(Track{}),
             options.track ? "the caller's, from --scenario or --manifest"
                           : "the default: give --scenario or --manifest for a scenario's",
             options.caller_reference.empty() ? nullptr : Open(options.caller_reference),
             {},
             {},
             {}};
  ChecklistReport r;
  r.directory = directory;
  for (const ItemSpec& spec : Items()) r.items.push_back(Evaluate(e, spec));
  r.loosened_fit_rerun = LoosenedFitRerun(e);
  JudgeParity(e, &r);
  Decide(&r);
  return r;
}

std::string ChecklistReport::ToMarkdown() const {
  std::ostringstream s;
  s << "## owval PR checklist: **" << VerdictName(verdict) << "**\n\n";
  if (!blocking.empty())
    for (std::size_t i = 0; i < blocking.size(); ++i)
      s << (i ? ", " : (verdict == Verdict::kIncomplete ? "Incomplete: " : "Blocking: "))
        << blocking[i] << (i + 1 == blocking.size() ? ".\n\n" : "");
  for (const ChecklistItem& i : items)
    s << "- " << (i.pass ? "✅" : "❌") << " **" << i.number << ". " << i.title << "** — " << i.detail
      << "\n";
  s << "- " << (parity_pass() ? "✅" : "❌") << " **parity gate** — ";
  if (parity) {
    s << parity->subject << ", " << parity->paired_frames << " paired frames: "
      << (!parity->pass()  ? "failed: " + parity->FailedGates()
          : !tracked_moves ? "the tracked quantity does not move"
          : failed_at_default_thresholds.empty()
              ? "every applicable gate passes"
              : "passes only with the loosened gates below; at DD001's defaults it fails: " +
                    failed_at_default_thresholds);
  } else {
    s << "not computed";
  }
  if (!parity_note.empty()) s << " (" << parity_note << ")";
  if (!loosened_thresholds.empty())
    s << "\n- ⚠️ **gates loosened by the caller** — " << LoosenedList(*this) << ": "
      << (!parity || !parity->pass() ? std::string("the candidate fails even these")
          : failed_at_default_thresholds.empty()
              ? std::string("the candidate passes the defaults too")
              : "at the defaults it FAILS: " + failed_at_default_thresholds);
  if (!loosened_fit_rerun.empty())
    s << "\n- ⚠️ **item 6 loosened by the caller** — " << loosened_fit_rerun
      << " (reported, not blocking: the rerun's own loss is judged against the threshold "
         "whatever the tolerance)";
  if (!candidate_note.empty()) s << "\n- ℹ️ **candidate** — " << candidate_note;
  s << "\n\nItems 1, 4, 5, 6 and the parity gate are required (else: not ready); 2 and 3 make "
       "the PR reviewable; 7–10 complete it.\n";
  if (parity) s << "\n" << compare::GatesMarkdownTable(parity->gates);
  return s.str();
}

nlohmann::json ChecklistReport::ToJson() const {
  nlohmann::json list = nlohmann::json::array();
  for (const ChecklistItem& i : items)
    list.push_back({{"item", i.number},
                    {"title", i.title},
                    {"present", i.present},
                    {"pass", i.pass},
                    {"detail", i.detail}});
  return {{"directory", directory.string()},
          {"verdict", VerdictName(verdict)},
          {"exit_code", exit_code()},
          {"blocking", blocking},
          {"items", list},
          {"parity", parity ? parity->ToJson() : nlohmann::json(nullptr)},
          {"parity_note", parity_note},
          {"loosened_thresholds", loosened_thresholds},
          {"failed_at_default_thresholds", failed_at_default_thresholds},
          {"loosened_fit_rerun", loosened_fit_rerun},
          {"candidate_note", candidate_note}};
}

}  // namespace owval::ci
