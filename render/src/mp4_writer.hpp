#pragma once
// H.264 in MP4 through libavcodec/libavformat (libx264, crf 18, yuv420p), in process.
#include <cstdint>
#include <string>
#include <vector>

struct AVFormatContext;
struct AVCodecContext;
struct AVStream;
struct AVFrame;
struct AVPacket;
struct SwsContext;

namespace owval::render::internal {

class Mp4Writer {
 public:
  // Writes `path`; errors name `shown` (the user's destination of a temporary), else `path`.
  // `comment`, when not empty, is the container's "comment" metadata (what made the video).
  Mp4Writer(const std::string& path, int width, int height, int fps, const std::string& shown = "",
            const std::string& comment = "");
  ~Mp4Writer();
  Mp4Writer(const Mp4Writer&) = delete;
  Mp4Writer& operator=(const Mp4Writer&) = delete;
  // RGBA pixels, top row first, width*height*4 bytes.
  void AddFrame(const std::vector<unsigned char>& rgba);
  // Flushes the encoder and writes the trailer.
  void Finish();
  std::size_t frames() const { return frames_; }

 private:
  void Drain(bool flushing);

  std::string path_;
  int width_, height_;
  AVFormatContext* format_ = nullptr;
  AVCodecContext* codec_ = nullptr;
  AVStream* stream_ = nullptr;
  AVFrame* frame_ = nullptr;
  AVPacket* packet_ = nullptr;
  SwsContext* sws_ = nullptr;
  std::size_t frames_ = 0;
  bool finished_ = false;
};

}  // namespace owval::render::internal
