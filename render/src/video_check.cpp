#include "owval/render/video_check.hpp"

#include <algorithm>
#include <cmath>

#include "mp4_reader.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/format.hpp"
#include "owval/base/json_file.hpp"
#include "owval/base/progress.hpp"
#include "side_by_side.hpp"

namespace owval::render {
namespace {

constexpr const char* kRecordFormat = "owval render sxs/1";
constexpr int kBlock = 16;  // pixels a side of the windows whose mean luma is compared

std::string TextField(const nlohmann::json& record, const char* key, const std::string& where) {
  const auto it = record.find(key);
  if (it == record.end() || !it->is_string())
    throw InputError(where, 0, std::string("render record: '") + key + "' is not a string");
  return it->get<std::string>();
}

double Luma(const unsigned char* rgba) {
  return 0.299 * rgba[0] + 0.587 * rgba[1] + 0.114 * rgba[2];
}

// Where windows of `size` pixels start along a side of `n`: every size / 2 pixels, the last one
// flush with the edge.
std::vector<int> WindowStarts(int n, int size) {
  std::vector<int> starts;
  for (int s = 0; s + size <= n; s += std::max(1, size / 2)) starts.push_back(s);
  if (starts.back() + size < n) starts.push_back(n - size);
  return starts;
}

// The luma (ITU-R BT.601 weights) of `drawn` minus that of `decoded`, averaged over every
// kBlock x kBlock window at a stride of half a window (so that a particle up to half a window
// across lies wholly inside one, wherever it falls): the largest magnitude, in luma levels.
double WorstBlockDifference(const std::vector<unsigned char>& drawn,
                            const std::vector<unsigned char>& decoded, int width, int height) {
  // A summed-area table of the difference: any window's sum from four entries.
  const std::size_t stride = std::size_t(width) + 1;
  std::vector<double> sums(stride * (std::size_t(height) + 1), 0);
  for (int y = 0; y < height; ++y) {
    double row = 0;
    for (int x = 0; x < width; ++x) {
      const std::size_t pixel = (std::size_t(y) * width + x) * 4;
      row += Luma(&drawn[pixel]) - Luma(&decoded[pixel]);
      sums[(y + 1) * stride + x + 1] = sums[y * stride + x + 1] + row;
    }
  }
  const int bw = std::min(kBlock, width), bh = std::min(kBlock, height);
  double worst = 0;
  for (int y : WindowStarts(height, bh))
    for (int x : WindowStarts(width, bw)) {
      const double sum = sums[(y + bh) * stride + x + bw] - sums[(y + bh) * stride + x] -
                         sums[y * stride + x + bw] + sums[y * stride + x];
      worst = std::max(worst, std::abs(sum) / (bw * bh));
    }
  return worst;
}

// Why a record cannot be drawn again, or "".
std::string CannotBeRedrawn(const nlohmann::json& record) {
  const double connections = record.value("connections", 0.0);
  if (connections == 0) return "";
  return "drawn with " + FormatNumber(connections, 9) +
         " elastic connections, which the check cannot draw again (render without --connections)";
}

// The largest window difference that moving every moving particle of the candidate by a tenth of
// the box makes in video frame 0: what a video whose options hide the runs (walls drawn opaque
// around them, frames a few pixels across, particles too faint) cannot show, whatever the runs.
// The particles move across the tracked axis, so that the printed tracked value stays the same.
double CandidateVisibility(internal::SideBySideFrames& frames, const RenderOptions& o,
                           const Box& box, float* distance_cu) {
  const Axis tracked = o.tracking ? o.tracking->axis : Axis::kY;
  const Axis across = tracked == Axis::kX ? Axis::kZ : Axis::kX;
  *distance_cu = box.extent(int(across)) > 0 ? 0.1f * box.extent(int(across)) : 10.0f;
  const std::vector<unsigned char> drawn = frames.Draw(0);
  return WorstBlockDifference(frames.DrawCandidateMoved(0, across, *distance_cu), drawn, o.width,
                              o.height);
}

}  // namespace

nlohmann::json SideBySideRecord(const RenderOptions& o) {
  return {{"record", kRecordFormat},
          {"size", std::to_string(o.width) + "x" + std::to_string(o.height)},
          {"view", o.view},
          {"boundary", BoundaryModeName(o.boundary)},
          {"liquid_opacity", o.liquid_opacity},
          {"point_size_px", o.point_size_px},
          {"fps", o.fps},
          {"max_frames", o.max_frames},
          {"title", o.title},
          {"reference_label", o.reference_label},
          {"candidate_label", o.candidate_label},
          {"draw_box", o.draw_box},
          {"track", o.tracking ? o.tracking->ToJson() : nlohmann::json()},
          {"connections", o.connections.size()}};
}

RenderOptions OptionsFromSideBySideRecord(const nlohmann::json& record, const std::string& where) {
  if (!record.is_object() || record.value("record", "") != kRecordFormat)
    throw InputError(where, 0,
                     std::string("render record: expected \"record\": \"") + kRecordFormat + "\"");
  RenderOptions o;
  try {
    ParseFrameSize(TextField(record, "size", where), &o);
  } catch (const InputError& e) {
    throw InputError(where, 0, std::string("render record: size: ") + e.what());
  }
  o.view = TextField(record, "view", where);
  o.boundary = ParseBoundaryMode(TextField(record, "boundary", where));
  o.liquid_opacity = float(NumberField(record, "liquid_opacity", where, "render record"));
  o.point_size_px = float(NumberField(record, "point_size_px", where, "render record"));
  const double fps = NumberField(record, "fps", where, "render record");
  const double max_frames = NumberField(record, "max_frames", where, "render record");
  if (fps < 1 || fps > 240 || fps != std::floor(fps) || max_frames < 0 || max_frames > 1e12 ||
      max_frames != std::floor(max_frames))
    throw InputError(where, 0, "render record: fps or max_frames out of range");
  o.fps = int(fps);
  o.max_frames = std::size_t(max_frames);
  o.title = TextField(record, "title", where);
  o.reference_label = TextField(record, "reference_label", where);
  o.candidate_label = TextField(record, "candidate_label", where);
  const auto box = record.find("draw_box");
  if (box == record.end() || !box->is_boolean())
    throw InputError(where, 0, "render record: 'draw_box' is not true or false");
  o.draw_box = box->get<bool>();
  const auto track = record.find("track");
  if (track != record.end() && !track->is_null())
    o.tracking = Track::FromJson(*track, where + ": render record track");
  return o;
}

namespace {

// Draws a sample of the video's frames again from the two runs and compares them with `video`'s,
// reading it as far as the last compared frame. False, with check->detail saying why, when its
// render record is missing or cannot be drawn again, or hides the candidate.
bool CompareSampledFrames(internal::Mp4Reader& video, FrameSource& reference,
                          FrameSource& candidate, const SideBySideCheckOptions& options,
                          const std::string& where, SideBySideCheck* check) {
  const std::string comment = video.Metadata("comment");
  if (comment.rfind(kSideBySideRecordPrefix, 0) != 0) {
    check->detail =
        "no owval render record: its pixels cannot be held to the two runs (render it with owval "
        "render sxs)";
    return false;
  }
  check->recorded = true;
  const nlohmann::json record = ParseJsonText(
      comment.substr(std::string(kSideBySideRecordPrefix).size()), where + " render record");
  RenderOptions o = OptionsFromSideBySideRecord(record, where);
  o.quiet = true;
  if (const std::string why = CannotBeRedrawn(record); !why.empty()) {
    check->detail = "its render record says it is " + why;
    return false;
  }
  if (video.width() != o.width || video.height() != o.height) {
    check->detail = "its render record says " + std::to_string(o.width) + "x" +
                    std::to_string(o.height) + ", the video is " + std::to_string(video.width()) +
                    "x" + std::to_string(video.height());
    return false;
  }
  internal::SideBySideFrames frames(reference, candidate, o);
  check->expected_frames = frames.size();
  check->candidate_visibility =
      CandidateVisibility(frames, o, candidate.header().box, &check->candidate_moved_cu);
  if (check->candidate_visibility < 2 * options.max_block_difference) {
    check->detail =
        "its frames do not show the candidate: drawn with its render record, every "
        "moving particle of the candidate moved " +
        FormatNumber(check->candidate_moved_cu, 3) + " cu changes no 16x16 window by more than " +
        FormatNumber(check->candidate_visibility, 3) + " luma levels (at least " +
        FormatNumber(2 * options.max_block_difference) +
        " needed: walls drawn over it, or frames too small)";
    return false;
  }
  const std::vector<std::size_t> compared =
      internal::SampleEvenly(frames.size(), options.max_frames_compared);
  Progress progress("check sxs.mp4", compared.size(), options.quiet);
  std::vector<unsigned char> decoded;
  for (std::size_t next = 0; next < compared.size();) {
    const std::size_t k = video.frames_decoded();
    const bool compare = compared[next] == k;
    if (!video.Next(compare ? &decoded : nullptr)) break;
    if (!compare) continue;
    const double d = WorstBlockDifference(frames.Draw(k), decoded, o.width, o.height);
    if (d > check->worst_block_difference || check->frames_compared == 0)
      check->worst_block_difference = d, check->worst_frame = k;
    ++check->frames_compared;
    progress.Update(++next);
  }
  return true;
}

}  // namespace

SideBySideCheck CheckSideBySide(const std::filesystem::path& mp4, FrameSource& reference,
                                FrameSource& candidate, const SideBySideCheckOptions& options) {
  const std::string where = mp4.string();
  internal::Mp4Reader video(where);
  SideBySideCheck check;
  bool compared = false;
  try {
    compared = CompareSampledFrames(video, reference, candidate, options, where, &check);
  } catch (const InputError&) {
    video.ReadToEnd();  // a damaged video is reported as damaged first
    throw;
  }
  // Every frame is decoded, whatever the record says: the caller's codec, shape and count.
  check.video = video.ReadToEnd();
  if (!compared) return check;
  if (check.video.decoded_frames != check.expected_frames) {
    check.detail = std::to_string(check.video.decoded_frames) +
                   " frames, where the two runs drawn with its render record make " +
                   std::to_string(check.expected_frames);
    return check;
  }
  check.pass = check.worst_block_difference <= options.max_block_difference;
  check.detail =
      (check.pass ? "" : "does not show these two runs: ") + std::to_string(check.frames_compared) +
      " frames drawn again from the two runs with its render record: worst 16x16 "
      "window " +
      FormatNumber(check.worst_block_difference, 3) + " luma levels apart (video frame " +
      std::to_string(check.worst_frame) + "; at most " +
      FormatNumber(options.max_block_difference) + "; the candidate's moving particles moved " +
      FormatNumber(check.candidate_moved_cu, 3) + " cu would change it by " +
      FormatNumber(check.candidate_visibility, 3) + ")";
  return check;
}

}  // namespace owval::render
