#pragma once
// Whether a side-by-side MP4 shows two given runs (the PR checklist's item 4). `owval render sxs`
// writes the options that decide its pixels into the file (the MP4's "comment" metadata:
// kSideBySideRecordPrefix and a JSON object, SideBySideRecord); CheckSideBySide reads them back,
// draws the video's frames again from the two trajectories with them, and compares each with the
// frame decoded from the file. owval's renderer is deterministic (OSMesa's llvmpipe, one camera
// from the reference's box, labels by FreeType), so what is left between the two is H.264's
// loss (crf 18, 4:2:0 chroma): a video of other runs, of another candidate, or of the reference
// twice shows particles where these runs have none.
//
// The record is the directory's own and could lie, but it only says how to draw: the frames are
// drawn from the trajectories the caller names, so a record that names other options than the
// video was made with fails as surely as a video of other runs. Options under which the runs
// cannot be seen (walls drawn opaque around them, frames a few pixels across) fail too: drawn
// with them, the candidate's moving particles moved by a tenth of the box must change the frame.
#include <cstddef>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "owval/render/read_back.hpp"
#include "owval/render/render.hpp"
#include "owval/trajectory/frame_source.hpp"

namespace owval::render {

inline constexpr const char* kSideBySideRecordPrefix = "owval render sxs ";

// {"record": "owval render sxs/1", "size": "1280x720", "view", "boundary", "liquid_opacity",
//  "point_size_px", "fps", "max_frames", "title", "reference_label", "candidate_label",
//  "draw_box", "track" (a Track's JSON or null), "connections" (how many were drawn)}.
nlohmann::json SideBySideRecord(const RenderOptions& options);
// The options back (connections left empty: the record holds their count only); InputError
// naming `where` and the field on anything else.
RenderOptions OptionsFromSideBySideRecord(const nlohmann::json& record, const std::string& where);

struct SideBySideCheckOptions {
  // The largest difference allowed between a decoded frame and the frame drawn again: the mean
  // luma (0-255) of a 16x16-pixel window (windows every 8 pixels), worst window. H.264's loss stays
  // far under it (measured in docs/checklist.md, item 4); a particle of the scenes' size where the
  // other has none moves its windows by tens of levels.
  double max_block_difference = 8;
  // Video frames compared, evenly spaced, first and last included (0: every frame). Every frame
  // is decoded either way. Drawing a 1280x720 frame again costs about what rendering it did
  // (one_sprig's pipeline directory, 300 frames: its checklist took 2.6 s before this check,
  // 3.7 s comparing 30 frames, 9.1 s comparing all), and a video of other runs differs wherever
  // the runs do, so a sample suffices.
  std::size_t max_frames_compared = 30;
  bool quiet = false;  // no progress line
};

struct SideBySideCheck {
  bool pass = false;
  bool recorded = false;            // the file carries owval's render record
  VideoInfo video;                  // the whole file decoded: codec, size, frames, duration
  std::size_t expected_frames = 0;  // the two runs drawn with the record's options
  std::size_t frames_compared = 0;
  double worst_block_difference = 0;  // luma levels, mean of a 16x16-pixel window
  std::size_t worst_frame = 0;        // video frame index of the worst window
  // Frame 0's worst window when every moving particle of the candidate is moved a tenth of the
  // box: below twice max_block_difference the video cannot show a candidate that far off, and
  // the check fails (walls drawn opaque around the particles, frames a few pixels across).
  double candidate_visibility = 0;
  float candidate_moved_cu = 0;  // how far, across the tracked axis
  std::string detail;            // one line: what was compared, or why it fails
};

// Reads `mp4` once, every frame (InputError when it cannot be opened or is damaged, as
// ProbeVideo says), and compares it with `reference` left and `candidate` right. Draws with
// OSMesa (EnvironmentError without it).
SideBySideCheck CheckSideBySide(const std::filesystem::path& mp4, FrameSource& reference,
                                FrameSource& candidate, const SideBySideCheckOptions& options = {});

}  // namespace owval::render
