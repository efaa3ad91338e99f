#pragma once
// Videos and images read back: frames decoded (libavformat and libavcodec, libpng), not guessed
// from a file's header. What the PR checklist (items 4 and 5) and the renderer's tests trust of an
// MP4 or a PNG.
#include <cstddef>
#include <filesystem>
#include <string>
#include <utility>

namespace owval::render {

struct VideoInfo {
  std::string codec;  // libavcodec's name ("h264")
  int width = 0, height = 0;
  std::size_t decoded_frames = 0;
  double duration_s = 0;  // the container's, 0 when it gives none
};

// Decodes every frame with the decoder's strict error checks. InputError when the file is missing,
// is not a video, decodes no frame, or is damaged: a packet refused, a frame concealed, or the
// container ending before its end.
VideoInfo ProbeVideo(const std::filesystem::path& path);

// Width and height of a PNG; InputError when it does not decode.
std::pair<int, int> ProbePng(const std::filesystem::path& path);

}  // namespace owval::render
