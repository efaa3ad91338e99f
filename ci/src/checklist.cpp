#include "owval/ci/checklist.hpp"

#include <algorithm>
#include <cmath>
#include <regex>
#include <sstream>

#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"
#include "owval/trajectory/formats.hpp"

namespace owval::ci {
namespace fs = std::filesystem;
namespace {

using Check = void (*)(const fs::path& dir, ChecklistItem* item);

nlohmann::json ReadJson(const fs::path& path) {
  try {
    return nlohmann::json::parse(ReadWholeFile(path));
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(path.string(), 0, std::string("not valid JSON: ") + e.what());
  }
}

// The first of `names` that exists in dir, or empty.
fs::path FirstExisting(const fs::path& dir, std::initializer_list<const char*> names) {
  for (const char* n : names)
    if (fs::exists(dir / n)) return dir / n;
  return {};
}

void CheckPrediction(const fs::path& dir, ChecklistItem* item) {
  const nlohmann::json p = ReadJson(dir / "prediction.json");
  if (!p.contains("predictions") || p["predictions"].empty())
    throw InputError((dir / "prediction.json").string(), 0,
                     "expected a non-empty \"predictions\" list");
  item->detail = std::to_string(p["predictions"].size()) + " predicted quantities";
  item->pass = true;
}

void CheckTrajectory(const fs::path& file, ChecklistItem* item) {
  TextReadOptions quiet;
  quiet.quiet = true;
  const Trajectory t = ReadTrajectory(file, quiet);
  for (float x : t.positions)
    if (!std::isfinite(x)) throw InputError(file.string(), 0, "contains NaN or Inf positions");
  item->detail = file.filename().string() + ": " + std::to_string(t.frame_count()) + " frames, " +
                 std::to_string(t.particle_count()) + " particles";
  item->pass = t.frame_count() >= 2;
  if (!item->pass) item->detail += " (expected at least 2 frames)";
}

void CheckReference(const fs::path& dir, ChecklistItem* item) {
  CheckTrajectory(FirstExisting(dir, {"reference.h5", "reference.txt"}), item);
}
void CheckCandidate(const fs::path& dir, ChecklistItem* item) {
  CheckTrajectory(FirstExisting(dir, {"candidate.h5", "candidate.txt"}), item);
}

void CheckVideo(const fs::path& dir, ChecklistItem* item) {
  const VideoInfo v = ProbeVideo(dir / "sxs.mp4");
  std::ostringstream s;
  s << v.codec << " " << v.width << "x" << v.height << ", " << v.decoded_frames
    << " frames decoded, " << v.duration_s << " s";
  // Two panels side by side: at least 1.5 times as wide as high.
  const bool two_panels = v.height > 0 && double(v.width) / v.height >= 1.5;
  if (!two_panels) s << " (not two panels wide: width/height < 1.5)";
  if (v.codec != "h264") s << " (expected h264)";
  item->detail = s.str();
  item->pass = two_panels && v.codec == "h264";
}

// The tracked value of a frames.json entry against the trajectory at the same frame.
bool ValueAgrees(const Trajectory& t, std::size_t frame, const nlohmann::json& track,
                 double value) {
  if (frame >= t.frame_count()) return false;
  const int axis = ParseAxis(track.value("axis", std::string("y")));
  double actual;
  if (track.contains("group") && !track["group"].get<std::string>().empty()) {
    actual = Centroid(t, frame, GroupIndices(t, track["group"].get<std::string>()))[axis];
  } else {
    actual = t.coordinate(frame, track.value("particle", std::size_t{0}), axis);
  }
  return std::abs(actual - value) <= 1e-3 * std::max(1.0, std::abs(actual));
}

void CheckFrames(const fs::path& dir, ChecklistItem* item) {
  const fs::path frames_dir = dir / "frames";
  std::size_t pngs = 0;
  if (fs::is_directory(frames_dir))
    for (const auto& e : fs::directory_iterator(frames_dir))
      if (e.path().extension() == ".png") {
        ProbePng(e.path());
        ++pngs;
      }
  const nlohmann::json j = ReadJson(frames_dir / "frames.json");
  TextReadOptions quiet;
  quiet.quiet = true;
  const Trajectory ref =
      ReadTrajectory(FirstExisting(dir, {"reference.h5", "reference.txt"}), quiet);
  const Trajectory cand =
      ReadTrajectory(FirstExisting(dir, {"candidate.h5", "candidate.txt"}), quiet);
  const nlohmann::json track = j.value("track", nlohmann::json::object());
  std::size_t agree = 0;
  for (const auto& f : j.at("frames")) {
    const bool ok = ValueAgrees(ref, f.at("reference_frame"), track, f.at("reference_value")) &&
                    ValueAgrees(cand, f.at("candidate_frame"), track, f.at("candidate_value"));
    agree += ok;
  }
  const std::size_t listed = j.at("frames").size();
  item->detail = std::to_string(pngs) + " PNGs decode; " + std::to_string(agree) + "/" +
                 std::to_string(listed) + " labelled values agree with the trajectories";
  item->pass = pngs >= 3 && listed >= 3 && agree == listed;
}

void CheckFitHistory(const fs::path& dir, ChecklistItem* item) {
  const fs::path path = dir / "fit" / "history.json";
  const nlohmann::json h = ReadJson(path);
  const bool converged = h.value("converged", false);
  const std::size_t iterations = h.contains("iterations") ? h["iterations"].size() : 0;
  std::ostringstream s;
  s << iterations << " iterations, stop reason: " << h.value("stop_reason", std::string("?"));
  if (h.contains("final") && h["final"].contains("loss"))
    s << ", final loss " << h["final"]["loss"].get<double>();
  item->detail = s.str();
  item->pass = converged && iterations > 0;
  if (!converged) item->detail += " (not converged)";
}

void CheckFdTests(const fs::path& dir, ChecklistItem* item) {
  const nlohmann::json j = ReadJson(dir / "fd_tests.json");
  std::size_t passed = 0, total = 0;
  for (const auto& t : j.at("tests")) {
    ++total;
    passed += t.value("pass", false);
  }
  item->detail =
      std::to_string(passed) + "/" + std::to_string(total) + " finite-difference tests pass";
  item->pass = total > 0 && passed == total;
}

void CheckParameters(const fs::path& dir, ChecklistItem* item) {
  const nlohmann::json j = ReadJson(dir / "parameters.json");
  const nlohmann::json values = j.contains("parameters") ? j["parameters"] : j;
  item->detail = std::to_string(values.size()) + " tuned values";
  item->pass = values.is_object() && !values.empty();
}

void CheckChanges(const fs::path& dir, ChecklistItem* item) {
  std::istringstream in(ReadWholeFile(dir / "changes.md"));
  static const std::regex list_item(R"(^\s*([-*+]|\d+\.)\s+\S)");
  std::size_t items = 0;
  for (std::string line; std::getline(in, line);) items += std::regex_search(line, list_item);
  item->detail = std::to_string(items) + " itemised changes";
  item->pass = items > 0;
}

void CheckReconcile(const fs::path& dir, ChecklistItem* item) {
  const nlohmann::json j = ReadJson(dir / "reconcile.json");
  item->pass = j.value("pass", false);
  item->detail = item->pass ? "every gap within tolerance" : "a gap exceeds its tolerance";
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
      {5, ">= 3 labelled frame PNGs with values", {"frames/frames.json"}, CheckFrames},
      {6, "fit convergence history", {"fit/history.json"}, CheckFitHistory},
      {7, "finite-difference tests for new kernels", {"fd_tests.json"}, CheckFdTests},
      {8, "tuned parameter values", {"parameters.json"}, CheckParameters},
      {9, "itemised substrate changes", {"changes.md"}, CheckChanges},
      {10, "prediction reconciled with measurement", {"reconcile.json"}, CheckReconcile},
  };
  return items;
}

ChecklistItem Evaluate(const fs::path& dir, const ItemSpec& spec) {
  ChecklistItem item;
  item.number = spec.number;
  item.title = spec.title;
  item.present = std::any_of(spec.files.begin(), spec.files.end(),
                             [&](const char* f) { return fs::exists(dir / f); });
  if (!item.present) {
    item.detail = std::string("missing: ") + spec.files.front();
    return item;
  }
  try {
    spec.check(dir, &item);
  } catch (const std::exception& e) {
    item.pass = false;
    item.detail = e.what();
  }
  return item;
}

Verdict Decide(const std::vector<ChecklistItem>& items) {
  auto fails = [&](int n) { return !items[std::size_t(n - 1)].pass; };
  if (fails(2) || fails(3)) return Verdict::kUnreviewable;
  if (fails(1) || fails(4) || fails(5) || fails(6)) return Verdict::kNotReady;
  if (fails(7) || fails(8) || fails(9) || fails(10)) return Verdict::kIncomplete;
  return Verdict::kReady;
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

ChecklistReport RunChecklist(const fs::path& directory) {
  if (!fs::is_directory(directory))
    throw InputError(directory.string(), 0, "not a directory of PR artifacts");
  ChecklistReport r;
  r.directory = directory;
  for (const ItemSpec& spec : Items()) r.items.push_back(Evaluate(directory, spec));
  r.verdict = Decide(r.items);
  return r;
}

std::string ChecklistReport::ToMarkdown() const {
  std::ostringstream s;
  s << "## owval PR checklist: **" << VerdictName(verdict) << "**\n\n";
  for (const ChecklistItem& i : items)
    s << "- " << (i.pass ? "✅" : "❌") << " **" << i.number << ". " << i.title << "** — " << i.detail
      << "\n";
  s << "\nItems 1, 4, 5, 6 are required (else: not ready); 2 and 3 make the PR reviewable; 7–10 "
       "complete it.\n";
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
          {"items", list}};
}

}  // namespace owval::ci
