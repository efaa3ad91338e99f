#pragma once
// A video file's frames decoded one at a time (libavformat, libavcodec, libswscale), strictly: a
// damaged stream is counted, never concealed and passed off as decoded. ProbeVideo reads every
// frame through it; CheckSideBySide also converts the frames it compares to RGBA, in the same pass.
#include <cstddef>
#include <string>
#include <vector>

#include "owval/render/read_back.hpp"

struct AVFormatContext;
struct AVCodecContext;
struct AVFrame;
struct AVPacket;
struct SwsContext;

namespace owval::render::internal {

class Mp4Reader {
 public:
  // InputError when `path` is missing, not a media file, or has no decodable video stream.
  explicit Mp4Reader(const std::string& path);
  ~Mp4Reader();
  Mp4Reader(const Mp4Reader&) = delete;
  Mp4Reader& operator=(const Mp4Reader&) = delete;

  // The container's metadata entry `key` ("" when absent).
  std::string Metadata(const char* key) const;
  int width() const { return width_; }
  int height() const { return height_; }
  std::size_t frames_decoded() const { return frames_; }

  // The next frame; unless `rgba` is null, its pixels as RGBA, top row first. False after the
  // last. A packet the decoder refuses or a frame it conceals is counted, not thrown.
  bool Next(std::vector<unsigned char>* rgba);
  // Decodes the frames Next has not given out (without converting them) and says what the whole
  // video held: InputError when no frame decoded, the container ended early, or any packet was
  // refused or frame concealed (the counts in the message).
  VideoInfo ReadToEnd();

 private:
  bool Feed();  // one more packet of the stream into the decoder; false at the end
  void ToRgba(std::vector<unsigned char>* rgba);

  std::string path_;
  int width_ = 0, height_ = 0, stream_ = -1;
  bool flushed_ = false, container_ended_early_ = false;
  std::size_t packets_ = 0, refused_ = 0, damaged_ = 0, frames_ = 0;
  AVFormatContext* format_ = nullptr;
  AVCodecContext* codec_ = nullptr;
  AVFrame* frame_ = nullptr;
  AVPacket* packet_ = nullptr;
  SwsContext* sws_ = nullptr;
};

}  // namespace owval::render::internal
