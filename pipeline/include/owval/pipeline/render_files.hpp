#pragma once
// `owval render`, `render sxs` and `frames` as library calls: trajectories named by path and
// read frame by frame, the options as a user writes them (a frame size "1280x720", the view
// "auto", panel names from the file names), the output checked before any frame is drawn, and
// phase 7's frame gate (owval compare --frames's) applied at the labelled frames.
//
//   pipeline::RenderRequest r;  r.trajectory = "run/trajectory.h5";  r.out = "run.mp4";
//   std::cout << pipeline::RenderVideoFile(r).ToText(r.out);
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "owval/compare/gates.hpp"
#include "owval/render/render.hpp"
#include "owval/trajectory/formats.hpp"
#include "owval/trajectory/track_choice.hpp"

namespace owval::pipeline {

struct RenderRequest {
  std::string trajectory;            // render: the one trajectory
  std::string reference, candidate;  // render sxs, frames
  std::string out;                   // the MP4 (render, sxs) or the frames' directory (frames)
  // fps, max_frames, liquid_opacity, title, draw_box as given; the rest is set from the fields
  // below.
  render::RenderOptions options;
  std::string size = "1280x720";      // WIDTHxHEIGHT of the whole frame
  std::string view = "auto";          // auto: worm for a worm trajectory, else iso; or a view name
  std::string boundary = "hidden";    // hidden | translucent | shown
  std::string label_ref, label_cand;  // panel names ("": from the file names)
  TrackChoice track;                  // printed on each panel (frames: particle 0 y by default)
  std::string connections;            // configuration or scenario whose connections are drawn
  std::filesystem::path data_dir;     // where scenario names are found
  TextReadOptions reading;            // text layout, progress line
  // frames only:
  std::string at = "0,15,100,200";  // reference frame indices
  std::optional<double> threshold;  // the frame gate's (default compare::ParityGates{}'s)
  bool gate = true;                 // false: the gate is printed but never fails the command
};

// render / render sxs: an odd size, an existing directory or a parent that cannot be written is
// refused (InputError) before anything is read, as is an output that is one of the inputs.
render::VideoSummary RenderVideoFile(const RenderRequest& request);
render::VideoSummary RenderSideBySideFiles(const RenderRequest& request);

struct FramesSummary {
  nlohmann::json frames;  // render::RenderFrames' numbers (also out/frames.json)
  std::vector<compare::Gate> gates;
  std::string at;
  bool gate = true;

  bool pass() const;  // no gate failed (n/a is no failure), or the gate is off
  // "frame gates at 0,15 (not gating: --no-gate)" and the gates' table.
  std::string GatesText() const;
  std::string ToText(const std::string& out) const;  // "wrote 4 frames to OUT"
};
// frames: labelled PNG frames at request.at and the gates there.
FramesSummary RenderFrameFiles(const RenderRequest& request);

}  // namespace owval::pipeline
