#pragma once
// An MP4's video frames decoded back to RGBA, one at a time (libavformat, libavcodec,
// libswscale): what CheckSideBySide compares with frames drawn again. Damage is the checklist's
// ProbeVideo's to find; a frame that does not decode here is an InputError.
#include <string>
#include <vector>

struct AVFormatContext;
struct AVCodecContext;
struct AVFrame;
struct AVPacket;
struct SwsContext;

namespace owval::render::internal {

class Mp4Reader {
 public:
  explicit Mp4Reader(const std::string& path);
  ~Mp4Reader();
  Mp4Reader(const Mp4Reader&) = delete;
  Mp4Reader& operator=(const Mp4Reader&) = delete;

  // The container's metadata entry `key` ("" when absent).
  std::string Metadata(const char* key) const;
  int width() const { return width_; }
  int height() const { return height_; }
  // The next frame as RGBA pixels, top row first; false after the last.
  bool Next(std::vector<unsigned char>* rgba);

 private:
  bool Feed();  // one more packet of the stream into the decoder; false at the end

  std::string path_;
  int width_ = 0, height_ = 0, stream_ = -1;
  bool flushed_ = false;
  AVFormatContext* format_ = nullptr;
  AVCodecContext* codec_ = nullptr;
  AVFrame* frame_ = nullptr;
  AVPacket* packet_ = nullptr;
  SwsContext* sws_ = nullptr;
};

}  // namespace owval::render::internal
