// Reading videos and images back: the checklist trusts nothing it has not decoded.
extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
}
#include <png.h>

#include <cstdio>
#include <memory>

#include "owval/base/errors.hpp"
#include "owval/ci/checklist.hpp"

namespace owval::ci {
namespace {

struct FormatCloser {
  void operator()(AVFormatContext* c) const { avformat_close_input(&c); }
};
struct CodecFreer {
  void operator()(AVCodecContext* c) const { avcodec_free_context(&c); }
};
struct PacketFreer {
  void operator()(AVPacket* p) const { av_packet_free(&p); }
};
struct FrameFreer {
  void operator()(AVFrame* f) const { av_frame_free(&f); }
};

// Frames out of the decoder; those it had to conceal (decode_error_flags, or flagged corrupt)
// are counted in `damaged` as well.
std::size_t DrainFrames(AVCodecContext* codec, AVFrame* frame, std::size_t* damaged) {
  std::size_t n = 0;
  while (avcodec_receive_frame(codec, frame) == 0) {
    ++n;
    if (frame->decode_error_flags != 0 || (frame->flags & AV_FRAME_FLAG_CORRUPT) != 0) ++*damaged;
  }
  return n;
}

}  // namespace

VideoInfo ProbeVideo(const std::filesystem::path& path) {
  const std::string name = path.string();
  AVFormatContext* raw = nullptr;
  if (avformat_open_input(&raw, name.c_str(), nullptr, nullptr) < 0)
    throw InputError(name, 0, "cannot open as a video (missing or not a media file)");
  std::unique_ptr<AVFormatContext, FormatCloser> format(raw);
  if (avformat_find_stream_info(format.get(), nullptr) < 0)
    throw InputError(name, 0, "no stream information");
  const int stream = av_find_best_stream(format.get(), AVMEDIA_TYPE_VIDEO, -1, -1, nullptr, 0);
  if (stream < 0) throw InputError(name, 0, "no video stream");
  const AVCodecParameters* par = format->streams[stream]->codecpar;
  const AVCodec* decoder = avcodec_find_decoder(par->codec_id);
  if (!decoder) throw InputError(name, 0, "no decoder for its codec");
  std::unique_ptr<AVCodecContext, CodecFreer> codec(avcodec_alloc_context3(decoder));
  avcodec_parameters_to_context(codec.get(), par);
  // A damaged stream is an error, not something to conceal and count as decoded.
  codec->err_recognition = AV_EF_CRCCHECK | AV_EF_BITSTREAM | AV_EF_BUFFER | AV_EF_EXPLODE;
  if (avcodec_open2(codec.get(), decoder, nullptr) < 0)
    throw InputError(name, 0, "cannot open decoder");
  VideoInfo info;
  info.codec = avcodec_get_name(par->codec_id);
  info.width = par->width;
  info.height = par->height;
  if (format->duration > 0) info.duration_s = double(format->duration) / AV_TIME_BASE;
  std::unique_ptr<AVPacket, PacketFreer> packet(av_packet_alloc());
  std::unique_ptr<AVFrame, FrameFreer> frame(av_frame_alloc());
  std::size_t packets = 0, refused = 0, damaged = 0;
  int read = 0;
  while ((read = av_read_frame(format.get(), packet.get())) >= 0) {
    if (packet->stream_index == stream) {
      ++packets;
      int status = avcodec_send_packet(codec.get(), packet.get());
      while (status == AVERROR(EAGAIN)) {  // decoder full: take frames out, then resend
        info.decoded_frames += DrainFrames(codec.get(), frame.get(), &damaged);
        status = avcodec_send_packet(codec.get(), packet.get());
      }
      if (status < 0) ++refused;
      info.decoded_frames += DrainFrames(codec.get(), frame.get(), &damaged);
    }
    av_packet_unref(packet.get());
  }
  avcodec_send_packet(codec.get(), nullptr);
  info.decoded_frames += DrainFrames(codec.get(), frame.get(), &damaged);
  if (info.decoded_frames == 0) throw InputError(name, 0, "no frame decodes");
  if (read != AVERROR_EOF) throw InputError(name, 0, "the container is damaged before its end");
  if (refused > 0 || damaged > 0 || info.decoded_frames != packets)
    throw InputError(name, 0,
                     "damaged: " + std::to_string(refused) + " of " + std::to_string(packets) +
                         " packets refused by the decoder, " + std::to_string(damaged) +
                         " frames concealed, " + std::to_string(info.decoded_frames) + " decoded");
  return info;
}

std::pair<int, int> ProbePng(const std::filesystem::path& path) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, path.c_str()))
    throw InputError(path.string(), 0, std::string("not a readable PNG: ") + image.message);
  image.format = PNG_FORMAT_RGBA;
  std::vector<png_byte> pixels(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, pixels.data(), 0, nullptr))
    throw InputError(path.string(), 0, std::string("PNG does not decode: ") + image.message);
  return {int(image.width), int(image.height)};
}

}  // namespace owval::ci
