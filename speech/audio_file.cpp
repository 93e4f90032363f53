#include "speech/audio_file.hpp"

#include <fmt/format.h>

#include <memory>
#include <string>

#include "facecore/error.hpp"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/channel_layout.h>
#include <libavutil/error.h>
#include <libavutil/log.h>
#include <libavutil/opt.h>
#include <libswresample/swresample.h>
}

namespace rostro::speech {
namespace {

std::string av_message(int code) {
  char text[AV_ERROR_MAX_STRING_SIZE] = {};
  av_strerror(code, text, sizeof text);
  return text;
}

struct FormatCloser {
  void operator()(AVFormatContext* c) const { avformat_close_input(&c); }
};
struct CodecFreer {
  void operator()(AVCodecContext* c) const { avcodec_free_context(&c); }
};
struct SwrFreer {
  void operator()(SwrContext* c) const { swr_free(&c); }
};
struct PacketFreer {
  void operator()(AVPacket* p) const { av_packet_free(&p); }
};
struct FrameFreer {
  void operator()(AVFrame* f) const { av_frame_free(&f); }
};

using SwrPtr = std::unique_ptr<SwrContext, SwrFreer>;

// A converter from `layout`/`format`/`in_rate` to mono signed 16-bit at `out_rate`.
SwrPtr make_converter(const AVChannelLayout& layout, AVSampleFormat format, int in_rate,
                      int out_rate) {
  AVChannelLayout mono = AV_CHANNEL_LAYOUT_MONO;
  AVChannelLayout in_layout = layout;  // FFmpeg 5.1 takes a non-const pointer
  SwrContext* raw = nullptr;
  if (swr_alloc_set_opts2(&raw, &mono, AV_SAMPLE_FMT_S16, out_rate, &in_layout, format, in_rate, 0,
                          nullptr) < 0 ||
      swr_init(raw) < 0) {
    swr_free(&raw);
    throw std::runtime_error("libswresample cannot convert this audio");
  }
  return SwrPtr(raw);
}

// Appends what `converter` gives for `count` input samples (nullptr input flushes).
void convert_into(SwrContext* converter, const std::uint8_t** input, int count,
                  std::vector<std::int16_t>& out) {
  const int room = swr_get_out_samples(converter, count);
  if (room <= 0) return;
  const std::size_t at = out.size();
  out.resize(at + static_cast<std::size_t>(room));
  auto* dest = reinterpret_cast<std::uint8_t*>(out.data() + at);
  const int made = swr_convert(converter, &dest, room, input, count);
  out.resize(at + static_cast<std::size_t>(std::max(made, 0)));
}

}  // namespace

Audio read_audio(const std::filesystem::path& path) {
  const std::string name = path.string();
  av_log_set_level(AV_LOG_QUIET);  // failures are reported once, below, as InputError
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw InputError(where(name, 0, "no such audio file"));

  AVFormatContext* raw_format = nullptr;
  if (const int rc = avformat_open_input(&raw_format, name.c_str(), nullptr, nullptr); rc < 0)
    throw InputError(where(name, 0, "not a recording FFmpeg can read (" + av_message(rc) + ")"));
  std::unique_ptr<AVFormatContext, FormatCloser> format(raw_format);
  if (avformat_find_stream_info(format.get(), nullptr) < 0)
    throw InputError(where(name, 0, "cannot read the recording's stream information"));
  const AVCodec* codec = nullptr;
  const int stream_index = av_find_best_stream(format.get(), AVMEDIA_TYPE_AUDIO, -1, -1, &codec, 0);
  if (stream_index < 0 || !codec) throw InputError(where(name, 0, "has no audio stream"));
  const AVStream* stream = format->streams[stream_index];

  std::unique_ptr<AVCodecContext, CodecFreer> decoder(avcodec_alloc_context3(codec));
  if (!decoder || avcodec_parameters_to_context(decoder.get(), stream->codecpar) < 0 ||
      avcodec_open2(decoder.get(), codec, nullptr) < 0)
    throw InputError(where(name, 0, fmt::format("cannot open its {} audio decoder", codec->name)));
  if (decoder->sample_rate <= 0) throw InputError(where(name, 0, "audio without a sample rate"));
  if (decoder->ch_layout.order == AV_CHANNEL_ORDER_UNSPEC)
    av_channel_layout_default(&decoder->ch_layout, decoder->ch_layout.nb_channels);

  Audio audio;
  audio.sample_rate = decoder->sample_rate;
  SwrPtr converter = make_converter(decoder->ch_layout, decoder->sample_fmt, decoder->sample_rate,
                                    decoder->sample_rate);
  std::unique_ptr<AVPacket, PacketFreer> packet(av_packet_alloc());
  std::unique_ptr<AVFrame, FrameFreer> frame(av_frame_alloc());
  int bad_packets = 0;
  auto drain = [&] {
    while (avcodec_receive_frame(decoder.get(), frame.get()) == 0) {
      convert_into(converter.get(), const_cast<const std::uint8_t**>(frame->extended_data),
                   frame->nb_samples, audio.samples);
      av_frame_unref(frame.get());
    }
  };
  while (av_read_frame(format.get(), packet.get()) >= 0) {
    if (packet->stream_index == stream_index) {
      if (avcodec_send_packet(decoder.get(), packet.get()) < 0) ++bad_packets;
      drain();
    }
    av_packet_unref(packet.get());
  }
  avcodec_send_packet(decoder.get(), nullptr);
  drain();
  convert_into(converter.get(), nullptr, 0, audio.samples);
  if (audio.samples.empty())
    throw InputError(where(name, 0,
                           bad_packets > 0 ? "no audio could be decoded (corrupt recording)"
                                           : "the recording has no samples"));
  return audio;
}

Audio resample(const Audio& audio, int sample_rate) {
  if (sample_rate == audio.sample_rate || audio.samples.empty()) {
    Audio copy = audio;
    copy.sample_rate = sample_rate;
    return copy;
  }
  AVChannelLayout mono = AV_CHANNEL_LAYOUT_MONO;
  SwrPtr converter = make_converter(mono, AV_SAMPLE_FMT_S16, audio.sample_rate, sample_rate);
  Audio out;
  out.sample_rate = sample_rate;
  const auto* input = reinterpret_cast<const std::uint8_t*>(audio.samples.data());
  convert_into(converter.get(), &input, static_cast<int>(audio.samples.size()), out.samples);
  convert_into(converter.get(), nullptr, 0, out.samples);
  return out;
}

}  // namespace rostro::speech
