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
constexpr int kBlock = 16;  // pixels a side of the blocks whose mean luma is compared

const char* BoundaryModeName(BoundaryMode mode) {
  switch (mode) {
    case BoundaryMode::kHidden:
      return "hidden";
    case BoundaryMode::kTranslucent:
      return "translucent";
    case BoundaryMode::kShown:
      return "shown";
  }
  return "hidden";
}

std::string TextField(const nlohmann::json& record, const char* key, const std::string& where) {
  const auto it = record.find(key);
  if (it == record.end() || !it->is_string())
    throw InputError(where, 0, std::string("render record: '") + key + "' is not a string");
  return it->get<std::string>();
}

// The mean luma (ITU-R BT.601 weights) of each kBlock x kBlock block of an RGBA image.
std::vector<double> BlockLuma(const std::vector<unsigned char>& rgba, int width, int height) {
  const int columns = (width + kBlock - 1) / kBlock, rows = (height + kBlock - 1) / kBlock;
  std::vector<double> sum(std::size_t(columns) * rows, 0), count(sum.size(), 0);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const unsigned char* p = &rgba[(std::size_t(y) * width + x) * 4];
      const std::size_t b = std::size_t(y / kBlock) * columns + x / kBlock;
      sum[b] += 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2];
      count[b] += 1;
    }
  for (std::size_t b = 0; b < sum.size(); ++b) sum[b] /= count[b];
  return sum;
}

double WorstBlockDifference(const std::vector<unsigned char>& drawn,
                            const std::vector<unsigned char>& decoded, int width, int height) {
  const std::vector<double> a = BlockLuma(drawn, width, height),
                            b = BlockLuma(decoded, width, height);
  double worst = 0;
  for (std::size_t k = 0; k < a.size(); ++k) worst = std::max(worst, std::abs(a[k] - b[k]));
  return worst;
}

// Why a record cannot show the runs however it is drawn, or "".
std::string CannotBeRedrawn(const nlohmann::json& record, const RenderOptions& o) {
  const double connections = record.value("connections", 0.0);
  if (connections != 0)
    return "drawn with " + FormatNumber(connections, 9) +
           " elastic connections, which the check cannot draw again (render without "
           "--connections)";
  // Particles too faint or too small to see would make any two runs look alike.
  if (o.liquid_opacity < 0.2f) return "its liquid is drawn at opacity below 0.2";
  if (o.point_size_px != 0 && o.point_size_px < 2) return "its particles are drawn below 2 pixels";
  return "";
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

SideBySideCheck CheckSideBySide(const std::filesystem::path& mp4, FrameSource& reference,
                                FrameSource& candidate, const SideBySideCheckOptions& options) {
  const std::string where = mp4.string();
  internal::Mp4Reader video(where);
  SideBySideCheck check;
  const std::string comment = video.Metadata("comment");
  if (comment.rfind(kSideBySideRecordPrefix, 0) != 0) {
    check.detail =
        "no owval render record: its pixels cannot be held to the two runs (render it with owval "
        "render sxs)";
    return check;
  }
  check.recorded = true;
  const nlohmann::json record = ParseJsonText(
      comment.substr(std::string(kSideBySideRecordPrefix).size()), where + " render record");
  RenderOptions o = OptionsFromSideBySideRecord(record, where);
  o.quiet = true;
  if (const std::string why = CannotBeRedrawn(record, o); !why.empty()) {
    check.detail = "its render record says it is " + why;
    return check;
  }
  if (video.width() != o.width || video.height() != o.height) {
    check.detail = "its render record says " + std::to_string(o.width) + "x" +
                   std::to_string(o.height) + ", the video is " + std::to_string(video.width()) +
                   "x" + std::to_string(video.height());
    return check;
  }
  internal::SideBySideFrames frames(reference, candidate, o);
  check.expected_frames = frames.size();
  const std::vector<std::size_t> compared =
      internal::SampleEvenly(frames.size(), options.max_frames_compared);
  Progress progress("check sxs.mp4", compared.size(), options.quiet);
  std::vector<unsigned char> decoded;
  std::size_t next = 0;  // into `compared`
  while (video.Next(&decoded)) {
    const std::size_t k = check.video_frames++;
    if (next == compared.size() || compared[next] != k) continue;
    const double d = WorstBlockDifference(frames.Draw(k), decoded, o.width, o.height);
    if (d > check.worst_block_difference || check.frames_compared == 0)
      check.worst_block_difference = d, check.worst_frame = k;
    ++check.frames_compared;
    progress.Update(++next);
  }
  const std::string measured = std::to_string(check.frames_compared) +
                               " frames drawn again from the two runs with its "
                               "render record: worst 16x16 block " +
                               FormatNumber(check.worst_block_difference, 3) +
                               " luma levels apart (video frame " +
                               std::to_string(check.worst_frame) + "; at most " +
                               FormatNumber(options.max_block_difference) + ")";
  if (check.video_frames != check.expected_frames) {
    check.detail = std::to_string(check.video_frames) +
                   " frames, where the two runs drawn with "
                   "its render record make " +
                   std::to_string(check.expected_frames);
    return check;
  }
  check.pass = check.worst_block_difference <= options.max_block_difference;
  check.detail = (check.pass ? "" : "does not show these two runs: ") + measured;
  return check;
}

}  // namespace owval::render
