#pragma once
// Mono 16-bit PCM audio and the WAV files rostro writes (speech) or reads (--audio).

#include <cstdint>
#include <filesystem>
#include <vector>

namespace rostro::speech {

struct Audio {
  int sample_rate = 22050;
  std::vector<std::int16_t> samples;  // mono

  double duration_s() const {
    return sample_rate > 0 ? static_cast<double>(samples.size()) / sample_rate : 0.0;
  }
};

// Writes a canonical 16-bit mono PCM WAV through a temporary file (never half a file).
void write_wav(const std::filesystem::path& path, const Audio& audio);

// Reads PCM (8/16/24/32-bit integer) or 32-bit float WAV; several channels are averaged.
// Throws InputError naming the file and what was expected.
Audio read_wav(const std::filesystem::path& path);

}  // namespace rostro::speech
