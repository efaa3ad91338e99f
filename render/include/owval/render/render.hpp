#pragma once
// Headless rendering of trajectories (phases 6 and 7): OSMesa (Mesa's off-screen llvmpipe) draws
// the particles, FreeType writes the labels, libavcodec/libavformat encode H.264 MP4 in process,
// libpng writes frames. Both panels of a comparison share one camera, computed once from the
// simulation box.
#include <array>
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "owval/trajectory/frame_source.hpp"
#include "owval/trajectory/track.hpp"
#include "owval/trajectory/trajectory.hpp"

namespace owval::render {

enum class BoundaryMode { kHidden, kTranslucent, kShown };
BoundaryMode ParseBoundaryMode(const std::string& name);  // hidden | translucent | shown
const char* BoundaryModeName(BoundaryMode mode);          // ParseBoundaryMode's inverse

struct RenderOptions {
  int width = 1280, height = 720;  // whole output frame (both panels in side-by-side mode)
  std::string view = "iso";        // iso | side | top | front | worm (see Camera::ForWorm)
  BoundaryMode boundary = BoundaryMode::kHidden;
  float liquid_opacity = 1.0f;
  float point_size_px = 0;  // 0: from the frame size and the particle spacing
  int fps = 30;
  std::size_t max_frames = 0;  // 0: every frame
  std::string title;           // a line across the top of the frame
  // Panel names of a side-by-side frame (e.g. "OpenCL" and "Metal").
  std::string reference_label = "reference", candidate_label = "candidate";
  // The simulation box's edges and its floor, where the scene has walls (a non-empty box).
  bool draw_box = true;
  std::optional<Track> tracking;  // print this tracked value on each panel
  // Elastic connections drawn as lines (particle index pairs, e.g. from a configuration's
  // [connection] block); empty: none.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> connections;
  bool quiet = false;
};

// A view of the simulation box, fixed for a whole video (both panels use the same one).
struct Camera {
  std::array<float, 16> projection, view;  // column-major, as OpenGL takes them
  static Camera FromBox(const Box& box, const std::string& view, float aspect);
  // The "worm" view: from above (down -y, z up the panel), centred on the non-boundary
  // particles' centroid at this frame and at the distance that fits them in ~90% of the panel
  // height (so the camera follows the worm and zooms as it curls).
  static Camera ForWorm(const Trajectory& trajectory, std::size_t frame, float aspect);
  // ForWorm when view is "worm", FromBox otherwise.
  static Camera ForFrame(const Trajectory& trajectory, std::size_t frame, const std::string& view,
                         float aspect);
  // Pixel (x from left, y from top) where a point lands in a panel of the given size.
  std::array<float, 2> Project(const std::array<float, 3>& point, int width, int height) const;
};

struct VideoSummary {
  std::size_t frames = 0;
  int width = 0, height = 0, fps = 0;
  double duration_s = 0;
  std::vector<std::string> notes;  // e.g. a time-step or log-step mismatch between the panels

  nlohmann::json ToJson(const std::filesystem::path& output) const;
  std::string ToText(const std::filesystem::path& output) const;  // "wrote OUT: N frames WxH ..."
};

// "1280x720" → width and height; InputError naming --size on anything else.
void ParseFrameSize(const std::string& text, RenderOptions* options);
// A video's frame size: 16 to 8192 pixels a side, both even (H.264 yuv420p); InputError naming
// --size otherwise. RenderVideo and RenderSideBySide check it before anything else.
void CheckVideoSize(const RenderOptions& options);

// A panel's default name: the trajectory file's stem, or its folder's name for the generic file
// names (position_buffer.txt, trajectory.h5: an owval run directory says more); `fallback` when
// the path is empty.
std::string PanelLabel(const std::filesystem::path& trajectory, const std::string& fallback);

// The FrameSource forms pull one frame at a time (memory O(particles), whatever the number of
// frames: issue 16); the Trajectory forms render a trajectory in memory the same way. The two
// sources of a comparison must be distinct objects.
VideoSummary RenderVideo(FrameSource& frames, const RenderOptions& options,
                         const std::filesystem::path& out_mp4);
VideoSummary RenderVideo(const Trajectory& trajectory, const RenderOptions& options,
                         const std::filesystem::path& out_mp4);
// Reference left, candidate right, paired by simulation time.
VideoSummary RenderSideBySide(FrameSource& reference, FrameSource& candidate,
                              const RenderOptions& options, const std::filesystem::path& out_mp4);
VideoSummary RenderSideBySide(const Trajectory& reference, const Trajectory& candidate,
                              const RenderOptions& options, const std::filesystem::path& out_mp4);

// PNG side-by-side frames at the given reference frame indices, each paired with the candidate
// frame at the same simulation time (PairFramesByTime), with each panel's tracked value and their
// difference printed; returns (and writes to out_dir/frames.json) the same numbers. The
// difference is also given relative to the reference's range over the common time window, as
// owval compare's frame gate measures it (a first pass over the paired reference frames finds that
// range). InputError, before anything is drawn or created,
// for an empty list, a frame listed twice or a frame without a partner. An earlier run's
// frame_N.png in out_dir that this run did not draw is removed; a folder created for a run that
// fails is removed.
nlohmann::json RenderFrames(FrameSource& reference, FrameSource& candidate,
                            const std::vector<std::size_t>& reference_frames,
                            const RenderOptions& options, const std::filesystem::path& out_dir);
nlohmann::json RenderFrames(const Trajectory& reference, const Trajectory& candidate,
                            const std::vector<std::size_t>& reference_frames,
                            const RenderOptions& options, const std::filesystem::path& out_dir);

// Process-wide, for the application to call once: libav* log only fatal errors (x264's
// statistics are noise on a user's terminal, and every error owval meets it reports itself, in
// one line, from libav's return codes: a damaged video in the checklist is the item's detail).
// A library never changes this behind its caller's back.
void SilenceCodecLogging();

// One frame as RGBA pixels (top row first), for tests and benchmarks.
std::vector<unsigned char> RenderFrameRgba(const Trajectory& trajectory, std::size_t frame,
                                           const RenderOptions& options);

}  // namespace owval::render
