#include "owval/pipeline/inspect.hpp"

#include "owval/base/errors.hpp"
#include "owval/base/format.hpp"
#include "owval/compare/metrics_json.hpp"
#include "owval/kinematics/midline.hpp"
#include "owval/kinematics/skeleton.hpp"
#include "owval/trajectory/frame_source.hpp"

namespace owval::pipeline {
namespace {

// "--from 0.5 s --to 0.2 s": the flags given, for messages.
std::string WindowFlags(const compare::SignalWindow& w) {
  std::string flags;
  if (w.start_s >= 0) flags += "--from " + FormatNumber(w.start_s, 6) + " s";
  if (w.end_s >= 0)
    flags += (flags.empty() ? "" : " ") + ("--to " + FormatNumber(w.end_s, 6) + " s");
  return flags;
}

// --from/--to against the frames' times, before any frame is read: the signal's own "the time
// window holds 0 samples" named neither flag nor the times the file holds.
void CheckWindow(const std::vector<double>& time_s, const compare::SignalWindow& w) {
  if (w.start_s < 0 && w.end_s < 0) return;  // the whole run: MeasureSignal's checks
  if (w.start_s >= 0 && w.end_s >= 0 && w.start_s >= w.end_s)
    throw InputError(WindowFlags(w) + ": expected --from before --to");
  std::size_t inside = 0;
  for (const double t : time_s)
    inside += !(w.start_s >= 0 && t < w.start_s) && !(w.end_s >= 0 && t > w.end_s);
  if (inside >= 2 || time_s.empty()) return;  // an empty file: the reader's message
  throw InputError(WindowFlags(w) + ": the window holds " + std::to_string(inside) +
                   " frame(s) of the trajectory's t = " + FormatNumber(time_s.front(), 6) + " .. " +
                   FormatNumber(time_s.back(), 6) + " s; expected a window with 2 or more");
}

}  // namespace

Inspection InspectTrajectory(const std::filesystem::path& path, const TextReadOptions& read,
                             const Track& track, const compare::SignalWindow& window) {
  Inspection i;
  i.file = path;
  TextReadReport report;
  const auto frames = OpenFrameSource(path, read, &report);
  RequireFrames(*frames, path, 2);  // a period, an amplitude: a signal over time
  i.layout = report.description;
  i.subject = track.Describe();
  CheckWindow(frames->header().time_s, window);
  i.metrics = compare::MeasureSignal(frames->header().time_s, track.Series(*frames), window);
  if (kinematics::IsWorm(frames->header())) i.worm = kinematics::AnalyseFrames(*frames);
  return i;
}

nlohmann::json Inspection::ToJson() const {
  nlohmann::json out = {{"file", file.string()},
                        {"layout", layout},
                        {"signal", subject},
                        {"metrics", compare::ToJson(metrics)}};
  if (worm) out["kinematics"] = worm->ToJson();
  return out;
}

std::string Inspection::ToText() const {
  std::string text = layout + "\n" + compare::ToText(metrics, subject);
  if (worm) text += "\nworm kinematics: " + worm->ToText();
  return text;
}

}  // namespace owval::pipeline
