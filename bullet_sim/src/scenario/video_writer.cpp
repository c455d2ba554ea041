#include "bullet_sim/scenario/video_writer.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>
}

#include <stdexcept>

namespace bullet_sim {

namespace {

std::string why(int code) {
  char text[AV_ERROR_MAX_STRING_SIZE] = {};
  av_strerror(code, text, sizeof text);
  return text;
}

const AVCodec* videoEncoder() {
  if (const AVCodec* h264 = avcodec_find_encoder(AV_CODEC_ID_H264)) return h264;
  return avcodec_find_encoder(AV_CODEC_ID_MPEG4);
}

}  // namespace

struct VideoWriter::Codec {
  std::string path;
  AVFormatContext* format = nullptr;
  AVCodecContext* context = nullptr;
  AVStream* stream = nullptr;
  AVFrame* frame = nullptr;
  AVPacket* packet = nullptr;
  SwsContext* scaler = nullptr;
  bool finished = false;

  void check(int code, const char* what) const {
    if (code < 0) throw std::runtime_error("video " + path + ": " + what + ": " + why(code));
  }

  /// Sends `input` (nullptr flushes) and writes every packet the encoder has ready.
  void encode(const AVFrame* input) {
    check(avcodec_send_frame(context, input), "encoding a frame");
    while (true) {
      const int received = avcodec_receive_packet(context, packet);
      if (received == AVERROR(EAGAIN) || received == AVERROR_EOF) return;
      check(received, "encoding a frame");
      av_packet_rescale_ts(packet, context->time_base, stream->time_base);
      packet->stream_index = stream->index;
      check(av_interleaved_write_frame(format, packet), "writing a frame");
    }
  }

  ~Codec() {
    sws_freeContext(scaler);
    av_packet_free(&packet);
    av_frame_free(&frame);
    avcodec_free_context(&context);
    if (format && !(format->oformat->flags & AVFMT_NOFILE)) avio_closep(&format->pb);
    avformat_free_context(format);
  }
};

VideoWriter::VideoWriter(const std::string& path, int width, int height, int fps)
    : codec_(std::make_unique<Codec>()) {
  Codec& c = *codec_;
  c.path = path;
  c.check(avformat_alloc_output_context2(&c.format, nullptr, "mp4", path.c_str()), "choosing the MP4 format");
  const AVCodec* encoder = videoEncoder();
  if (!encoder)
    throw std::runtime_error("video " + path + ": FFmpeg has neither an H.264 nor an MPEG-4 encoder");
  c.stream = avformat_new_stream(c.format, nullptr);
  c.context = avcodec_alloc_context3(encoder);
  c.frame = av_frame_alloc();
  c.packet = av_packet_alloc();
  if (!c.stream || !c.context || !c.frame || !c.packet)
    throw std::runtime_error("video " + path + ": out of memory");
  c.context->width = width;
  c.context->height = height;
  c.context->time_base = AVRational{1, fps};
  c.context->framerate = AVRational{fps, 1};
  c.context->pix_fmt = AV_PIX_FMT_YUV420P;
  c.context->gop_size = fps;
  c.context->thread_count = 1;  // a run is pinned to one thread
  if (encoder->id == AV_CODEC_ID_H264) av_opt_set(c.context->priv_data, "preset", "veryfast", 0);
  if (encoder->id == AV_CODEC_ID_MPEG4) c.context->bit_rate = 2000000;
  if (c.format->oformat->flags & AVFMT_GLOBALHEADER) c.context->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
  c.check(avcodec_open2(c.context, encoder, nullptr), "opening the encoder");
  c.check(avcodec_parameters_from_context(c.stream->codecpar, c.context), "setting up the stream");
  c.stream->time_base = c.context->time_base;
  c.check(avio_open(&c.format->pb, path.c_str(), AVIO_FLAG_WRITE), "opening the file");
  c.check(avformat_write_header(c.format, nullptr), "writing the header");
  c.frame->format = AV_PIX_FMT_YUV420P;
  c.frame->width = width;
  c.frame->height = height;
  c.check(av_frame_get_buffer(c.frame, 0), "making a frame");
  c.scaler = sws_getContext(width, height, AV_PIX_FMT_RGBA, width, height, AV_PIX_FMT_YUV420P, SWS_BILINEAR,
                            nullptr, nullptr, nullptr);
  if (!c.scaler) throw std::runtime_error("video " + path + ": cannot convert RGBA to YUV");
}

VideoWriter::~VideoWriter() {
  try {
    finish();
  } catch (const std::exception&) {
  }
}

void VideoWriter::add(const Image& image) {
  Codec& c = *codec_;
  if (image.width != c.context->width || image.height != c.context->height)
    throw std::invalid_argument("video " + c.path + ": a frame of another size");
  c.check(av_frame_make_writable(c.frame), "making a frame");
  const uint8_t* planes[1] = {image.rgba.data()};
  const int strides[1] = {4 * image.width};
  sws_scale(c.scaler, planes, strides, 0, image.height, c.frame->data, c.frame->linesize);
  c.frame->pts = frames_++;
  c.encode(c.frame);
}

void VideoWriter::finish() {
  Codec& c = *codec_;
  if (c.finished) return;
  c.finished = true;
  c.encode(nullptr);
  c.check(av_write_trailer(c.format), "writing the index");
}

}  // namespace bullet_sim
