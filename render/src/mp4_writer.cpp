#include "mp4_writer.hpp"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/imgutils.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>
}

#include "owval/base/errors.hpp"
#include "owval/render/render.hpp"

namespace owval::render::internal {
namespace {
void Check(int status, const std::string& path, const char* what) {
  if (status < 0) {
    char message[AV_ERROR_MAX_STRING_SIZE] = {};
    av_strerror(status, message, sizeof message);
    throw InputError(path, 0, std::string(what) + ": " + message);
  }
}
}  // namespace

Mp4Writer::Mp4Writer(const std::string& file, int width, int height, int fps,
                     const std::string& shown, const std::string& comment)
    : path_(shown.empty() ? file : shown), width_(width), height_(height) {
  const std::string& path = path_;  // the name in messages
  if (width % 2 || height % 2)
    throw InputError(path, 0, "video width and height must be even for yuv420p");
  Check(avformat_alloc_output_context2(&format_, nullptr, "mp4", file.c_str()), path,
        "cannot create MP4 container");
  const AVCodec* encoder = avcodec_find_encoder_by_name("libx264");
  if (!encoder)
    throw EnvironmentError("libavcodec has no libx264 encoder (install libavcodec with x264)");
  stream_ = avformat_new_stream(format_, nullptr);
  codec_ = avcodec_alloc_context3(encoder);
  codec_->width = width;
  codec_->height = height;
  codec_->time_base = AVRational{1, fps};
  codec_->framerate = AVRational{fps, 1};
  codec_->pix_fmt = AV_PIX_FMT_YUV420P;
  codec_->gop_size = fps;
  // No B-frames: libx264 keeps whole frames buffered for them (a 1280x720 render took 214 MB
  // with them, whatever the trajectory's length: issue 16); the file is about 4% larger.
  codec_->max_b_frames = 0;
  av_opt_set(codec_->priv_data, "crf", "18", 0);
  av_opt_set(codec_->priv_data, "preset", "superfast", 0);
  // Bounded encoder memory (issue 16). libx264's default frame threads each encode a frame of
  // their own, with its own reconstructed and look-ahead frames (a 1280x720 frame with its
  // half-pel planes is about 5 MB); slice threads split each frame between the threads instead,
  // so one set of frames serves all of them, with the same parallelism and no frames of delay.
  // No scene-cut detection: it keeps a quarter-size copy of each queued frame to compare, and
  // the GOP (a keyframe every second) already bounds how far a seek decodes. A 1280x720 render
  // takes 10-15 MB less; its file is about 1.5% larger.
  codec_->thread_type = FF_THREAD_SLICE;
  av_opt_set(codec_->priv_data, "x264-params", "scenecut=0", 0);
  if (format_->oformat->flags & AVFMT_GLOBALHEADER) codec_->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
  Check(avcodec_open2(codec_, encoder, nullptr), path, "cannot open the H.264 encoder");
  Check(avcodec_parameters_from_context(stream_->codecpar, codec_), path, "codec parameters");
  stream_->time_base = codec_->time_base;
  if (!comment.empty())
    Check(av_dict_set(&format_->metadata, "comment", comment.c_str(), 0), path, "metadata");
  Check(avio_open(&format_->pb, file.c_str(), AVIO_FLAG_WRITE), path, "cannot open for writing");
  Check(avformat_write_header(format_, nullptr), path, "cannot write the MP4 header");
  frame_ = av_frame_alloc();
  frame_->format = AV_PIX_FMT_YUV420P;
  frame_->width = width;
  frame_->height = height;
  Check(av_frame_get_buffer(frame_, 0), path, "frame buffer");
  packet_ = av_packet_alloc();
  sws_ = sws_getContext(width, height, AV_PIX_FMT_RGBA, width, height, AV_PIX_FMT_YUV420P,
                        SWS_BILINEAR, nullptr, nullptr, nullptr);
}

Mp4Writer::~Mp4Writer() {
  sws_freeContext(sws_);
  av_packet_free(&packet_);
  av_frame_free(&frame_);
  avcodec_free_context(&codec_);
  if (format_) {
    if (format_->pb) avio_closep(&format_->pb);
    avformat_free_context(format_);
  }
}

void Mp4Writer::AddFrame(const std::vector<unsigned char>& rgba) {
  Check(av_frame_make_writable(frame_), path_, "frame not writable");
  const uint8_t* source[1] = {rgba.data()};
  const int stride[1] = {4 * width_};
  sws_scale(sws_, source, stride, 0, height_, frame_->data, frame_->linesize);
  frame_->pts = static_cast<int64_t>(frames_++);
  Check(avcodec_send_frame(codec_, frame_), path_, "encoding failed");
  Drain(false);
}

void Mp4Writer::Drain(bool flushing) {
  while (true) {
    const int status = avcodec_receive_packet(codec_, packet_);
    if (status == AVERROR(EAGAIN) || (flushing && status == AVERROR_EOF)) return;
    Check(status, path_, "encoding failed");
    // Every frame lasts one tick; without a duration the muxer's edit list cuts the last frame.
    if (packet_->duration == 0) packet_->duration = 1;
    av_packet_rescale_ts(packet_, codec_->time_base, stream_->time_base);
    packet_->stream_index = stream_->index;
    Check(av_interleaved_write_frame(format_, packet_), path_, "cannot write a packet");
  }
}

void Mp4Writer::Finish() {
  if (finished_) return;
  finished_ = true;
  Check(avcodec_send_frame(codec_, nullptr), path_, "flushing the encoder");
  Drain(true);
  Check(av_write_trailer(format_), path_, "cannot write the MP4 trailer");
  avio_closep(&format_->pb);
}

}  // namespace owval::render::internal

namespace owval::render {

void SilenceCodecLogging() { av_log_set_level(AV_LOG_FATAL); }

}  // namespace owval::render
