#pragma once
// Recognition stage for text: espeak-ng, embedded as a library, turns text into audio and
// phoneme events. Each phoneme event carries the sample at which the phoneme starts, so
// phoneme times come from the same sample counter as the audio: no second clock.

#include <string>
#include <vector>

#include "speech/audio.hpp"
#include "speech/phoneme.hpp"

namespace rostro::speech {

struct SynthOptions {
  std::string voice = "es";  // an espeak-ng voice name or language: es, es-419, pt-br, pt, en-us...
  int rate_wpm = 0;          // 0 keeps espeak-ng's default (175 words per minute)
  int pitch = -1;            // 0..100, -1 keeps the default
};

struct Synthesis {
  Audio audio;
  std::vector<RawPhoneme> phonemes;  // in time order, contiguous, last ends at audio end
};

// Throws InputError when the voice is unknown, or std::runtime_error when espeak-ng
// cannot start. Thread-safe (espeak-ng itself is global: calls are serialised).
Synthesis synthesize(const std::string& text, const SynthOptions& options);

}  // namespace rostro::speech
