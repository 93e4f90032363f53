#include "speech/audio.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>

#include "facecore/atomic_file.hpp"
#include "facecore/error.hpp"

namespace rostro::speech {
namespace {

void put_u32(std::string& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}
void put_u16(std::string& out, std::uint16_t v) {
  out.push_back(static_cast<char>(v & 0xff));
  out.push_back(static_cast<char>((v >> 8) & 0xff));
}
std::uint32_t get_u32(const unsigned char* p) {
  return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
         (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}
std::uint16_t get_u16(const unsigned char* p) {
  return static_cast<std::uint16_t>(p[0] | (p[1] << 8));
}

}  // namespace

void write_wav(const std::filesystem::path& path, const Audio& audio) {
  const auto data_bytes = static_cast<std::uint32_t>(audio.samples.size() * 2);
  std::string out;
  out.reserve(44 + data_bytes);
  out += "RIFF";
  put_u32(out, 36 + data_bytes);
  out += "WAVEfmt ";
  put_u32(out, 16);
  put_u16(out, 1);  // PCM
  put_u16(out, 1);  // mono
  put_u32(out, static_cast<std::uint32_t>(audio.sample_rate));
  put_u32(out, static_cast<std::uint32_t>(audio.sample_rate * 2));
  put_u16(out, 2);
  put_u16(out, 16);
  out += "data";
  put_u32(out, data_bytes);
  for (std::int16_t s : audio.samples) put_u16(out, static_cast<std::uint16_t>(s));
  AtomicFile file(path);
  file.write(out);
  file.commit();
}

Audio read_wav(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(where(path.string(), 0, "cannot open the WAV file"));
  std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)),
                                   std::istreambuf_iterator<char>());
  const auto fail = [&](const std::string& what) {
    return InputError(where(path.string(), 0, what));
  };
  if (bytes.size() < 12 || std::memcmp(bytes.data(), "RIFF", 4) != 0 ||
      std::memcmp(bytes.data() + 8, "WAVE", 4) != 0)
    throw fail("not a RIFF/WAVE file");
  int format = 0, channels = 0, rate = 0, bits = 0;
  const unsigned char* data = nullptr;
  std::size_t data_size = 0;
  std::size_t pos = 12;
  while (pos + 8 <= bytes.size()) {
    const unsigned char* chunk = bytes.data() + pos;
    const std::size_t size = get_u32(chunk + 4);
    const std::size_t body = pos + 8;
    const std::size_t available = std::min(size, bytes.size() - body);
    if (std::memcmp(chunk, "fmt ", 4) == 0 && available >= 16) {
      format = get_u16(chunk + 8);
      channels = get_u16(chunk + 10);
      rate = static_cast<int>(get_u32(chunk + 12));
      bits = get_u16(chunk + 22);
      if (format == 0xFFFE && available >= 26) format = get_u16(chunk + 32);  // extensible
    } else if (std::memcmp(chunk, "data", 4) == 0) {
      data = bytes.data() + body;
      data_size = available;  // a truncated data chunk keeps what is there
    }
    pos = body + size + (size & 1);
  }
  if (format == 0) throw fail("no 'fmt ' chunk");
  if (!data) throw fail("no 'data' chunk");
  const bool pcm = format == 1 && (bits == 8 || bits == 16 || bits == 24 || bits == 32);
  const bool flt = format == 3 && bits == 32;
  if (!pcm && !flt)
    throw fail(
        "unsupported WAV encoding (expected 8/16/24/32-bit PCM or 32-bit float), got format " +
        std::to_string(format) + " with " + std::to_string(bits) + " bits");
  if (channels < 1 || rate <= 0) throw fail("bad channel count or sample rate");
  const std::size_t bytes_per_sample = static_cast<std::size_t>(bits / 8);
  const std::size_t frame_bytes = bytes_per_sample * static_cast<std::size_t>(channels);
  const std::size_t frames = data_size / frame_bytes;
  Audio audio;
  audio.sample_rate = rate;
  audio.samples.resize(frames);
  for (std::size_t f = 0; f < frames; ++f) {
    double sum = 0.0;
    for (int c = 0; c < channels; ++c) {
      const unsigned char* p =
          data + f * frame_bytes + static_cast<std::size_t>(c) * bytes_per_sample;
      double v = 0.0;
      if (flt) {
        float x;
        std::memcpy(&x, p, 4);
        v = x;
      } else if (bits == 8) {
        v = (p[0] - 128) / 128.0;
      } else if (bits == 16) {
        v = static_cast<std::int16_t>(get_u16(p)) / 32768.0;
      } else if (bits == 24) {
        std::int32_t x = p[0] | (p[1] << 8) | (p[2] << 16);
        if (x & 0x800000) x -= 0x1000000;
        v = x / 8388608.0;
      } else {
        v = static_cast<std::int32_t>(get_u32(p)) / 2147483648.0;
      }
      sum += v;
    }
    const double mono = std::clamp(sum / channels, -1.0, 1.0);
    audio.samples[f] = static_cast<std::int16_t>(std::lround(mono * 32767.0));
  }
  return audio;
}

}  // namespace rostro::speech
