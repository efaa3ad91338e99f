// owval inspect TRAJ: phase-3 measurements of one coordinate of a particle or group centroid.
#include <iostream>

#include "command.hpp"
#include "owval/pipeline/inspect.hpp"
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
  const pipeline::Inspection i = pipeline::InspectTrajectory(
      a.path, Reading(a.layout), a.track.Over(Track{}), {a.start_s, a.end_s});
  std::cout << (a.json ? i.ToJson().dump(2) + "\n" : i.ToText());
}

void SetUpInspect(CLI::App& app) {
  auto args = std::make_shared<InspectArgs>();
  CLI::App* cmd = app.add_subcommand(
      "inspect", "Phase 3: period, amplitude, equilibrium, drift, damping, settling");
  AddInput(cmd, "trajectory", &args->path, "Trajectory file (position_buffer.txt or .h5)");
  AddTrackFlags(cmd, &args->track, "", "Measured");
  // NaN or a negative time was taken as "no bound": the whole window, silently.
  cmd->add_option("--from", args->start_s, "Window start (s)")->check(NonNegative());
  cmd->add_option("--to", args->end_s, "Window end (s)")->check(NonNegative());
  AddLayoutFlag(cmd, &args->layout);
  AddJsonFlag(cmd, &args->json, "the measurements");
  cmd->callback([args] { RunInspect(*args); });
}

const bool inspect_registered = RegisterCommand(&SetUpInspect);

}  // namespace
}  // namespace owval::cli
