// owval render / render sxs / frames: phase 6 and 7 pictures, without any display.
#include <algorithm>
#include <iostream>

#include "command.hpp"
#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/format.hpp"
#include "owval/compare/parity.hpp"
#include "owval/kinematics/midline.hpp"
#include "owval/render/render.hpp"
#include "owval/trajectory/formats.hpp"
#include "resolve.hpp"

namespace owval::cli {
namespace {

struct RenderArgs {
  std::string trajectory, reference, candidate, out;
  std::string size = "1280x720", view = "auto", boundary = "hidden", at = "0,15,100,200", title;
  int fps = 30;
  std::size_t max_frames = 0;
  float liquid_opacity = 1.0f;
  TrackFlags track;
  std::string label_ref, label_cand;
  bool no_box = false, no_gate = false;
  std::optional<double> threshold;
  std::string connections;  // configuration whose [connection] block is drawn
  bool json = false;
};

void RequireOut(const RenderArgs& a) {  // before any work starts
  if (a.out.empty()) throw InputError("-o/--out is required");
}

// render and render sxs write one MP4: an odd --size, an existing directory or a parent that
// cannot be written is refused here, not after the frames were rendered.
void RequireVideoOut(const RenderArgs& a) {
  RequireOut(a);
  render::RenderOptions size;
  render::ParseFrameSize(a.size, &size);
  render::CheckVideoSize(size);  // --size 101x101: refused now, not by the encoder
  CheckOutputPath(a.out);
  CheckOutputIsNotAnInput(a.out, {a.trajectory, a.reference, a.candidate, a.connections});
}

// shown: the (reference) trajectory; "auto" frames a worm with the worm view, anything else iso.
render::RenderOptions Options(const RenderArgs& a, const Trajectory& shown) {
  render::RenderOptions o;
  render::ParseFrameSize(a.size, &o);
  o.view = a.view != "auto" ? a.view : kinematics::IsWorm(shown) ? "worm" : "iso";
  o.boundary = render::ParseBoundaryMode(a.boundary);
  o.fps = a.fps;
  o.max_frames = a.max_frames;
  o.liquid_opacity = a.liquid_opacity;
  o.title = a.title;
  o.quiet = Flags().quiet;
  if (!a.connections.empty()) o.connections = engine::ConnectionPairs(ResolveConfig(a.connections));
  if (a.track.given()) o.tracking = a.track.Over(Track{});
  o.draw_box = !a.no_box;
  o.reference_label =
      a.label_ref.empty() ? render::PanelLabel(a.reference, "reference") : a.label_ref;
  o.candidate_label =
      a.label_cand.empty() ? render::PanelLabel(a.candidate, "candidate") : a.label_cand;
  return o;
}

// Phase 7's frame gate at the rendered frames, as owval compare --frames computes it: exit 1
// when a frame breaks it (unless --no-gate), and the gate printed either way.
void GateFrames(const RenderArgs& a, FrameSource& ref, FrameSource& cand,
                const render::RenderOptions& o, const std::vector<std::size_t>& at) {
  compare::ParityOptions parity;
  parity.track = *o.tracking;
  parity.sample_frames = at;
  parity.quiet = Flags().quiet;
  if (a.threshold) parity.gates.frame = {*a.threshold, compare::ThresholdSource::kFlag};
  const std::vector<compare::Gate> gates = compare::SampledFrameGates(ref, cand, parity);
  std::cerr << "frame gates at " << a.at << (a.no_gate ? " (not gating: --no-gate)" : "") << "\n"
            << compare::GatesTextTable(gates);
  const bool failed = std::any_of(gates.begin(), gates.end(), [](const compare::Gate& g) {
    return g.status == compare::GateStatus::kFail;
  });
  if (failed && !a.no_gate) SetExitCode(kExitGateFailed);
}

void Print(const render::VideoSummary& s, const std::string& out, bool json) {
  if (json) {
    std::cout << s.ToJson(out).dump(2) << "\n";
    return;
  }
  for (const auto& note : s.notes) std::cerr << "owval: note: " << note << "\n";
  std::cout << s.ToText(out) << "\n";
}

void AddCommon(CLI::App* cmd, RenderArgs* a, const std::string& out_help) {
  cmd->add_option("-o,--out", a->out, out_help + " (required)");
  cmd->add_option("--size", a->size, "WIDTHxHEIGHT of the whole frame (default 1280x720)");
  cmd->add_option("--view", a->view,
                  "auto (worm for worm trajectories, else iso), iso, side, top, front, or worm "
                  "(camera on the worm, following its centroid, liquid translucent)")
      ->check(CLI::IsMember({"auto", "iso", "side", "top", "front", "worm"}));
  cmd->add_option("--boundary", a->boundary, "hidden, translucent or shown")
      ->check(CLI::IsMember({"hidden", "translucent", "shown"}));
  cmd->add_option("--liquid-opacity", a->liquid_opacity, "0..1")->check(Fraction());
  AddTrackFlags(cmd, &a->track, "track-", "Print this");
  cmd->add_option("--label-ref", a->label_ref, "Left panel's name (default: from the file name)");
  cmd->add_option("--label-cand", a->label_cand,
                  "Right panel's name (default: from the file name)");
  cmd->add_flag("--no-box", a->no_box, "Do not draw the simulation box and its floor");
  cmd->add_option("--title", a->title, "Title line");
  cmd->add_option("--connections", a->connections,
                  "Draw the elastic connections of this configuration (file or scenario) as lines");
  cmd->add_flag("--json", a->json, "Machine-readable summary");
}

void SetUp(CLI::App& app) {
  auto a = std::make_shared<RenderArgs>();
  CLI::App* cmd = app.add_subcommand(
      "render", "Phase 6: render a trajectory to H.264 MP4 (OSMesa, no display)");
  cmd->add_option("trajectory", a->trajectory, "Trajectory to render");
  AddCommon(cmd, a.get(), "Output MP4 file (not a directory)");
  cmd->add_option("--fps", a->fps, "Frames per second")->check(CLI::Range(1, 240));
  cmd->add_option("--max-frames", a->max_frames,
                  "Cap on rendered frames, evenly spaced (0, the default: every frame)")
      ->check(Count());
  CLI::App* sxs =
      cmd->add_subcommand("sxs", "Side by side: reference left, candidate right, one camera");
  sxs->add_option("reference", a->reference)->required();
  sxs->add_option("candidate", a->candidate)->required();
  AddCommon(sxs, a.get(), "Output MP4 file (not a directory)");
  sxs->add_option("--fps", a->fps, "Frames per second")->check(CLI::Range(1, 240));
  sxs->add_option("--max-frames", a->max_frames,
                  "Cap on rendered frames, evenly spaced (0, the default: every frame)")
      ->check(Count());
  sxs->callback([a] {
    RequireVideoOut(*a);
    const auto ref = OpenTrajectoryArgument(a->reference);  // frame by frame
    const auto cand = OpenTrajectoryArgument(a->candidate);
    Print(render::RenderSideBySide(*ref, *cand, Options(*a, ref->header()), a->out), a->out,
          a->json);
  });
  cmd->callback([a, cmd] {
    if (cmd->got_subcommand("sxs")) return;
    if (a->trajectory.empty())
      throw InputError("owval render: expected a trajectory (or: owval render sxs REF CAND)");
    RequireVideoOut(*a);
    const auto t = OpenTrajectoryArgument(a->trajectory);  // frame by frame
    Print(render::RenderVideo(*t, Options(*a, t->header()), a->out), a->out, a->json);
  });
  CLI::App* frames =
      app.add_subcommand("frames", "Phase 7: labelled side-by-side PNG frames and frames.json");
  frames->add_option("reference", a->reference)->required();
  frames->add_option("candidate", a->candidate)->required();
  frames->add_option("--at", a->at, "Reference frame indices, e.g. 0,15,100,200");
  AddCommon(frames, a.get(), "Output directory (frame_N.png and frames.json)");
  frames
      ->add_option("--threshold", a->threshold,
                   "Frame gate: |delta| / reference range must stay below (default " +
                       FormatNumber(compare::ParityGates{}.frame.value) + ")")
      ->check(Positive());
  frames->footer(
      "Gates at the sampled frames (as owval compare --frames): frames: |delta| of the tracked "
      "value / the reference's range (--threshold); frames.group_centroids: each moving group's "
      "centroid distance / the box's largest extent (compare's centroid_distance threshold). "
      "Exit 1 when one fails.");
  frames->add_flag("--no-gate", a->no_gate, "Exit 0 even when a frame breaks the gate");
  frames->callback([a] {
    RenderArgs args = *a;
    if (!args.track.given()) args.track.particle = 0;
    RequireOut(args);
    const auto ref = OpenTrajectoryArgument(a->reference);  // frame by frame
    const auto cand = OpenTrajectoryArgument(a->candidate);
    const render::RenderOptions options = Options(args, ref->header());
    const std::vector<std::size_t> at = ParseIndexList(a->at, "--at");
    const auto result = render::RenderFrames(*ref, *cand, at, options, a->out);
    GateFrames(*a, *ref, *cand, options, at);
    std::cout << (a->json
                      ? result.dump(2)
                      : "wrote " + std::to_string(result["frames"].size()) + " frames to " + a->out)
              << "\n";
  });
}

const bool registered = RegisterCommand(&SetUp);

}  // namespace
}  // namespace owval::cli
