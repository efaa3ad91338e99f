#include "mp4_reader.hpp"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libswscale/swscale.h>
}

#include "owval/base/errors.hpp"

namespace owval::render {
namespace internal {

Mp4Reader::Mp4Reader(const std::string& path) : path_(path) {
  if (avformat_open_input(&format_, path.c_str(), nullptr, nullptr) < 0)
    throw InputError(path, 0, "cannot open as a video (missing or not a media file)");
  if (avformat_find_stream_info(format_, nullptr) < 0)
    throw InputError(path, 0, "no stream information");
  stream_ = av_find_best_stream(format_, AVMEDIA_TYPE_VIDEO, -1, -1, nullptr, 0);
  if (stream_ < 0) throw InputError(path, 0, "no video stream");
  const AVCodecParameters* par = format_->streams[stream_]->codecpar;
  const AVCodec* decoder = avcodec_find_decoder(par->codec_id);
  if (!decoder) throw InputError(path, 0, "no decoder for its codec");
  codec_ = avcodec_alloc_context3(decoder);
  if (!codec_ || avcodec_parameters_to_context(codec_, par) < 0)
    throw InputError(path, 0, "cannot open decoder");
  // A damaged stream is an error, not something to conceal and count as decoded.
  codec_->err_recognition = AV_EF_CRCCHECK | AV_EF_BITSTREAM | AV_EF_BUFFER | AV_EF_EXPLODE;
  if (avcodec_open2(codec_, decoder, nullptr) < 0) throw InputError(path, 0, "cannot open decoder");
  width_ = par->width;
  height_ = par->height;
  frame_ = av_frame_alloc();
  packet_ = av_packet_alloc();
}

Mp4Reader::~Mp4Reader() {
  sws_freeContext(sws_);
  av_packet_free(&packet_);
  av_frame_free(&frame_);
  avcodec_free_context(&codec_);
  avformat_close_input(&format_);
}

std::string Mp4Reader::Metadata(const char* key) const {
  const AVDictionaryEntry* entry = av_dict_get(format_->metadata, key, nullptr, 0);
  return entry ? entry->value : "";
}

bool Mp4Reader::Feed() {
  int read = 0;
  while ((read = av_read_frame(format_, packet_)) >= 0) {
    const bool ours = packet_->stream_index == stream_;
    if (ours) {
      ++packets_;
      // Called only when the decoder has no frame to give, so it takes the packet or refuses it.
      if (avcodec_send_packet(codec_, packet_) < 0) ++refused_;
    }
    av_packet_unref(packet_);
    if (ours) return true;
  }
  container_ended_early_ = read != AVERROR_EOF;
  avcodec_send_packet(codec_, nullptr);  // the end: the decoder gives out what it holds
  flushed_ = true;
  return false;
}

bool Mp4Reader::Next(std::vector<unsigned char>* rgba) {
  while (true) {
    const int status = avcodec_receive_frame(codec_, frame_);
    if (status == 0) {
      ++frames_;
      if (frame_->decode_error_flags != 0 || (frame_->flags & AV_FRAME_FLAG_CORRUPT) != 0)
        ++damaged_;
      if (rgba) ToRgba(rgba);
      return true;
    }
    if (status == AVERROR_EOF || flushed_) return false;
    if (status != AVERROR(EAGAIN)) ++damaged_;  // the decoder failed on what it was given
    Feed();
  }
}

void Mp4Reader::ToRgba(std::vector<unsigned char>* rgba) {
  if (frame_->width != width_ || frame_->height != height_)
    throw InputError(path_, 0, "a frame's size differs from the stream's");
  sws_ = sws_getCachedContext(sws_, width_, height_, AVPixelFormat(frame_->format), width_, height_,
                              AV_PIX_FMT_RGBA, SWS_BILINEAR, nullptr, nullptr, nullptr);
  if (!sws_) throw InputError(path_, 0, "its pixel format cannot be converted to RGBA");
  rgba->resize(std::size_t(width_) * height_ * 4);
  uint8_t* target[1] = {rgba->data()};
  const int stride[1] = {4 * width_};
  sws_scale(sws_, frame_->data, frame_->linesize, 0, height_, target, stride);
}

VideoInfo Mp4Reader::ReadToEnd() {
  while (Next(nullptr)) {
  }
  if (frames_ == 0) throw InputError(path_, 0, "no frame decodes");
  if (container_ended_early_) throw InputError(path_, 0, "the container is damaged before its end");
  if (refused_ > 0 || damaged_ > 0 || frames_ != packets_)
    throw InputError(path_, 0,
                     "damaged: " + std::to_string(refused_) + " of " + std::to_string(packets_) +
                         " packets refused by the decoder, " + std::to_string(damaged_) +
                         " frames concealed, " + std::to_string(frames_) + " decoded");
  VideoInfo info;
  info.codec = avcodec_get_name(format_->streams[stream_]->codecpar->codec_id);
  info.width = width_;
  info.height = height_;
  info.decoded_frames = frames_;
  if (format_->duration > 0) info.duration_s = double(format_->duration) / AV_TIME_BASE;
  return info;
}

}  // namespace internal

VideoInfo ProbeVideo(const std::filesystem::path& path) {
  return internal::Mp4Reader(path.string()).ReadToEnd();
}

}  // namespace owval::render
