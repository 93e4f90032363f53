#pragma once
// Recordings in any format FFmpeg reads (WAV, FLAC, MP3, Ogg, M4A...), mixed down to mono
// 16-bit PCM, and resampling to the rate an analysis needs. Both go through FFmpeg's own
// libraries (libavformat, libavcodec, libswresample), not a subprocess.

#include <filesystem>

#include "speech/audio.hpp"

namespace rostro::speech {

// Decodes the file's best audio stream at its own sample rate; channels are averaged.
// Throws InputError naming the file for a missing, unreadable or audio-less file, or one
// with no samples at all.
Audio read_audio(const std::filesystem::path& path);

// The same signal at `sample_rate` (band-limited by libswresample). Returns a copy when the
// rate already matches.
Audio resample(const Audio& audio, int sample_rate);

}  // namespace rostro::speech
