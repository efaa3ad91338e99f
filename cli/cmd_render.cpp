// owval render / render sxs / frames: phase 6 and 7 pictures, without any display
// (pipeline/render_files.hpp).
#include <iostream>

#include "command.hpp"
#include "owval/base/format.hpp"
#include "owval/compare/parity.hpp"
#include "owval/pipeline/render_files.hpp"

namespace owval::cli {
namespace {

struct RenderArgs {
  pipeline::RenderRequest request;
  bool json = false;
};

// The request as parsed, progress lines following --quiet.
const pipeline::RenderRequest& Request(RenderArgs& a) {
  a.request.reading.quiet = QuietMode();
  return a.request;
}

void Print(const render::VideoSummary& s, const std::string& out, bool json) {
  if (json) {
    std::cout << s.ToJson(out).dump(2) << "\n";
    return;
  }
  for (const auto& note : s.notes) std::cerr << "owval: note: " << note << "\n";
  std::cout << s.ToText(out) << "\n";
}

void AddCommon(CLI::App* cmd, RenderArgs* a, const std::string& out_help, bool video) {
  pipeline::RenderRequest& r = a->request;
  AddOut(cmd, &r.out, out_help + " (required)");
  cmd->add_option("--size", r.size, "WIDTHxHEIGHT of the whole frame (default " + r.size + ")");
  cmd->add_option("--view", r.view,
                  "auto (worm for worm trajectories, else iso), iso, side, top, front, or worm "
                  "(camera on the worm, following its centroid, liquid translucent)")
      ->check(CLI::IsMember({"auto", "iso", "side", "top", "front", "worm"}));
  cmd->add_option("--boundary", r.boundary, "hidden, translucent or shown")
      ->check(CLI::IsMember({"hidden", "translucent", "shown"}));
  cmd->add_option("--liquid-opacity", r.options.liquid_opacity, "0..1")->check(Fraction());
  AddTrackFlags(cmd, &r.track, "track-", "Print this");
  cmd->add_option("--label-ref", r.label_ref, "Left panel's name (default: from the file name)");
  cmd->add_option("--label-cand", r.label_cand, "Right panel's name (default: from the file name)");
  cmd->add_flag_callback(
      "--no-box", [&r] { r.options.draw_box = false; },
      "Do not draw the simulation box and its floor");
  cmd->add_option("--title", r.options.title, "Title line");
  cmd->add_option("--connections", r.connections,
                  "Draw the elastic connections of this configuration (file or scenario) as lines");
  AddJsonFlag(cmd, &a->json, "a summary");
  if (!video) return;
  cmd->add_option("--fps", r.options.fps, "Frames per second")->check(CLI::Range(1, 240));
  cmd->add_option("--max-frames", r.options.max_frames,
                  "Cap on rendered frames, evenly spaced (0, the default: every frame)")
      ->check(Count());
}

void SetUpRender(CLI::App& app) {
  auto a = std::make_shared<RenderArgs>();
  pipeline::RenderRequest& r = a->request;
  r.data_dir = DataDir();
  CLI::App* cmd = app.add_subcommand(
      "render", "Phase 6: render a trajectory to H.264 MP4 (OSMesa, no display)");
  cmd->add_option("trajectory", r.trajectory, "Trajectory to render")->check(GivenName());
  AddCommon(cmd, a.get(), "Output MP4 file (not a directory)", true);
  CLI::App* sxs =
      cmd->add_subcommand("sxs", "Side by side: reference left, candidate right, one camera");
  AddInput(sxs, "reference", &r.reference);
  AddInput(sxs, "candidate", &r.candidate);
  AddCommon(sxs, a.get(), "Output MP4 file (not a directory)", true);
  sxs->callback([a] { Print(RenderSideBySideFiles(Request(*a)), a->request.out, a->json); });
  cmd->callback([a, cmd] {
    if (cmd->got_subcommand("sxs")) return;
    if (a->request.trajectory.empty())
      throw InputError("owval render: expected a trajectory (or: owval render sxs REF CAND)");
    Print(RenderVideoFile(Request(*a)), a->request.out, a->json);
  });
  CLI::App* frames =
      app.add_subcommand("frames", "Phase 7: labelled side-by-side PNG frames and frames.json");
  AddInput(frames, "reference", &r.reference);
  AddInput(frames, "candidate", &r.candidate);
  frames->add_option("--at", r.at, "Reference frame indices, e.g. 0,15,100,200");
  AddCommon(frames, a.get(), "Output directory (frame_N.png and frames.json)", false);
  frames
      ->add_option("--threshold", r.threshold,
                   "Frame gate: |delta| / reference range must stay below (default " +
                       FormatNumber(compare::ParityGates{}.frame.value) + ")")
      ->check(Positive());
  frames->footer(
      "Gates at the sampled frames (as owval compare --frames): frames: |delta| of the tracked "
      "value / the reference's range (--threshold); frames.group_centroids: each moving group's "
      "centroid distance / the box's largest extent (compare's centroid_distance threshold). "
      "Exit 1 when one fails.");
  frames->add_flag_callback(
      "--no-gate", [&r] { r.gate = false; }, "Exit 0 even when a frame breaks the gate");
  frames->callback([a] {
    const pipeline::FramesSummary s = pipeline::RenderFrameFiles(Request(*a));
    // --quiet silences the table, never the reason for exit 1.
    if (!QuietMode() || !s.pass()) std::cerr << s.GatesText();
    std::cout << (a->json ? s.frames.dump(2) : s.ToText(a->request.out)) << "\n";
    if (!s.pass()) SetExitCode(kExitGateFailed);
  });
}

const bool render_registered = RegisterCommand(&SetUpRender);

}  // namespace
}  // namespace owval::cli
