#pragma once
// Is there a voice in a recording at all? Checked before any recognition, so silence, noise
// or a steady tone is refused in one line instead of animated as speech. Speech is voiced
// (periodic at a pitch of 50-400 Hz) in a good share of its frames, and its loudness rises
// and falls with the syllables; hiss is not periodic, a held tone does not rise and fall.

#include <string>

#include "speech/audio.hpp"

namespace rostro::speech {

struct SpeechPresence {
  double loudest_db = -120.0;       // the loudest 40 ms, dBFS
  double voiced_share = 0.0;        // share of all frames that are loud and periodic
  double loudness_spread_db = 0.0;  // standard deviation of loudness over the loud frames
};

SpeechPresence measure_speech_presence(const Audio& audio);

// Throws InputError naming `name` when the recording is silent, or has too few voiced frames,
// or too steady a loudness, to hold speech.
void require_speech(const Audio& audio, const std::string& name);

}  // namespace rostro::speech
