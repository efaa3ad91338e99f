// owval inspect TRAJ: phase-3 measurements of one coordinate of a particle or group centroid.
#include <cstdio>
#include <iostream>

#include "command.hpp"
#include "owval/base/errors.hpp"
#include "owval/compare/metrics_json.hpp"
#include "owval/kinematics/kinematics.hpp"
#include "owval/kinematics/midline.hpp"
#include "owval/trajectory/formats.hpp"
#include "owval/trajectory/track.hpp"
#include "resolve.hpp"

namespace owval::cli {
namespace {

struct InspectArgs {
  std::string path;
  TrackFlags track;
  double start_s = -1, end_s = -1;
  std::string layout = "auto";
  bool json = false;
};

void RunInspect(const InspectArgs& a) {
  TextReadReport read;
  const auto frames = OpenTrajectoryArgument(a.path, a.layout, &read);  // frame by frame
  const Track track = a.track.Over(Track{});
  const std::vector<double> series = track.Series(*frames);
  const std::string subject = track.Describe();
  const compare::SignalMetrics m =
      compare::MeasureSignal(frames->header().time_s, series, {a.start_s, a.end_s});
  std::optional<kinematics::Report> worm;  // a worm also gets its kinematics (issue 15): whole
  if (kinematics::IsWorm(frames->header()))
    worm = kinematics::Analyse(
        kinematics::SkeletonsFromTrajectory(ReadTrajectoryArgument(a.path, a.layout)));
  if (a.json) {
    nlohmann::json out = {{"file", a.path},
                          {"layout", read.description},
                          {"signal", subject},
                          {"metrics", compare::ToJson(m)}};
    if (worm) out["kinematics"] = worm->ToJson();
    std::cout << out.dump(2) << "\n";
  } else {
    std::printf("%s\n%s", read.description.c_str(), compare::ToText(m, subject).c_str());
    if (worm) std::printf("\nworm kinematics: %s", worm->ToText().c_str());
  }
}

void SetUp(CLI::App& app) {
  auto args = std::make_shared<InspectArgs>();
  CLI::App* cmd = app.add_subcommand(
      "inspect", "Phase 3: period, amplitude, equilibrium, drift, damping, settling");
  cmd->add_option("trajectory", args->path, "Trajectory file (position_buffer.txt or .h5)")
      ->required();
  AddTrackFlags(cmd, &args->track, "", "Measured");
  cmd->add_option("--from", args->start_s, "Window start (s)");
  cmd->add_option("--to", args->end_s, "Window end (s)");
  cmd->add_option("--layout", args->layout, "Text layout: auto, opencl or native")
      ->check(CLI::IsMember({"auto", "opencl", "native"}));
  cmd->add_flag("--json", args->json, "Machine-readable output");
  cmd->callback([args] { RunInspect(*args); });
}

const bool registered = RegisterCommand(&SetUp);

}  // namespace
}  // namespace owval::cli
