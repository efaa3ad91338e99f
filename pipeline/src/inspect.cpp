#include "owval/pipeline/inspect.hpp"

#include "owval/compare/metrics_json.hpp"
#include "owval/kinematics/midline.hpp"
#include "owval/kinematics/skeleton.hpp"
#include "owval/trajectory/frame_source.hpp"

namespace owval::pipeline {

Inspection InspectTrajectory(const std::filesystem::path& path, const TextReadOptions& read,
                             const Track& track, const compare::SignalWindow& window) {
  Inspection i;
  i.file = path;
  TextReadReport report;
  const auto frames = OpenFrameSource(path, read, &report);
  i.layout = report.description;
  i.subject = track.Describe();
  i.metrics = compare::MeasureSignal(frames->header().time_s, track.Series(*frames), window);
  if (kinematics::IsWorm(frames->header()))
    i.worm = kinematics::Analyse(kinematics::SkeletonsFromFrames(*frames));
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
