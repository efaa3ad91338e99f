#include "owval/pipeline/render_files.hpp"

#include <algorithm>

#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/index_list.hpp"
#include "owval/compare/parity.hpp"
#include "owval/engine/config.hpp"
#include "owval/kinematics/midline.hpp"
#include "owval/scenarios/scenario.hpp"
#include "owval/trajectory/frame_source.hpp"

namespace owval::pipeline {
namespace {

void RequireOut(const RenderRequest& r) {  // before any work starts
  if (r.out.empty()) throw InputError("-o/--out is required");
}

// A video is one MP4: an odd --size, an existing directory or a parent that cannot be written is
// refused here, not after the frames were rendered.
void RequireVideoOut(const RenderRequest& r) {
  RequireOut(r);
  render::RenderOptions size;
  render::ParseFrameSize(r.size, &size);
  render::CheckVideoSize(size);  // --size 101x101: refused now, not by the encoder
  CheckOutputPath(r.out);
  CheckOutputIsNotAnInput(r.out, {r.trajectory, r.reference, r.candidate, r.connections});
}

// shown: the (reference) trajectory; "auto" frames a worm with the worm view, anything else iso.
render::RenderOptions Options(const RenderRequest& r, const Trajectory& shown) {
  render::RenderOptions o = r.options;
  render::ParseFrameSize(r.size, &o);
  o.view = r.view != "auto" ? r.view : kinematics::IsWorm(shown) ? "worm" : "iso";
  o.boundary = render::ParseBoundaryMode(r.boundary);
  o.quiet = r.reading.quiet;
  if (!r.connections.empty())
    o.connections = engine::ConnectionPairs(scenarios::ResolveConfig(r.connections, r.data_dir));
  if (r.track.given()) o.tracking = r.track.Over(Track{});
  o.reference_label =
      r.label_ref.empty() ? render::PanelLabel(r.reference, "reference") : r.label_ref;
  o.candidate_label =
      r.label_cand.empty() ? render::PanelLabel(r.candidate, "candidate") : r.label_cand;
  return o;
}

}  // namespace

render::VideoSummary RenderVideoFile(const RenderRequest& r) {
  RequireVideoOut(r);
  const auto shown = OpenFrameSource(r.trajectory, r.reading);  // frame by frame
  return render::RenderVideo(*shown, Options(r, shown->header()), r.out);
}

render::VideoSummary RenderSideBySideFiles(const RenderRequest& r) {
  RequireVideoOut(r);
  const auto reference = OpenFrameSource(r.reference, r.reading);  // frame by frame
  const auto candidate = OpenFrameSource(r.candidate, r.reading);
  return render::RenderSideBySide(*reference, *candidate, Options(r, reference->header()), r.out);
}

FramesSummary RenderFrameFiles(const RenderRequest& request) {
  RenderRequest r = request;
  if (!r.track.given()) r.track.particle = 0;
  RequireOut(r);
  const auto reference = OpenFrameSource(r.reference, r.reading);  // frame by frame
  const auto candidate = OpenFrameSource(r.candidate, r.reading);
  const render::RenderOptions options = Options(r, reference->header());
  const std::vector<std::size_t> at = ParseIndexList(r.at, "--at");
  FramesSummary s;
  // Phase 7's frame gate at the rendered frames, as owval compare --frames computes it. First:
  // it reads every paired frame, so a corrupt one is refused before any PNG is written (it was
  // found after the directory had been committed: exit 2 with frames.json in place).
  compare::ParityOptions parity;
  parity.track = *options.tracking;
  parity.sample_frames = at;
  parity.quiet = r.reading.quiet;
  if (r.threshold) parity.gates.frame = {*r.threshold, compare::ThresholdSource::kFlag};
  s.gates = compare::CompareSampledFrames(*reference, *candidate, parity).gates();
  s.frames = render::RenderFrames(*reference, *candidate, at, options, r.out);
  s.at = r.at;
  s.gate = r.gate;
  return s;
}

bool FramesSummary::pass() const {
  return !gate || std::none_of(gates.begin(), gates.end(), [](const compare::Gate& g) {
    return g.status == compare::GateStatus::kFail;
  });
}

std::string FramesSummary::GatesText() const {
  return "frame gates at " + at + (gate ? "" : " (not gating: --no-gate)") + "\n" +
         compare::GatesTextTable(gates);
}

std::string FramesSummary::ToText(const std::string& out) const {
  return "wrote " + std::to_string(frames["frames"].size()) + " frames to " + out;
}

}  // namespace owval::pipeline
