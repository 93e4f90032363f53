#pragma once
// Recognition for a recorded voice with its transcript, in any language espeak-ng speaks,
// with no acoustic model: espeak-ng says the transcript (the reference, whose phoneme times
// are exact), both signals become MFCC features, dynamic time warping matches reference
// frames to recording frames, and each phoneme boundary is carried along that match into
// recording time.

#include <string>
#include <vector>

#include "speech/audio.hpp"
#include "speech/dtw.hpp"
#include "speech/espeak_synth.hpp"
#include "speech/mfcc.hpp"
#include "speech/phoneme.hpp"

namespace rostro::speech {

struct AlignmentOptions {
  SynthOptions reference;  // the voice (and rate) that says the transcript
  // espeak-ng variants of that voice tried as the reference (its own male voice and a
  // female one); the one the recording matches best is kept. A voice already naming a
  // variant ("en-us+m3") is used alone.
  std::vector<std::string> voice_variants = {"", "+f3"};
  double reference_pad_s = 0.3;  // silence added before and after the reference
  // Say the reference again at the recording's pace when its voiced span is more than about
  // 15 % longer or shorter (only when `reference.rate_wpm` is 0, espeak-ng's default).
  bool match_tempo = true;
  MfccOptions features;
  WarpOptions warping;
  // The transcript check: matched speech frames must lie closer than this share of their
  // distance to the reference played backwards (same voice, same sounds, wrong order).
  // Readings of the right text measured 0.16-0.75 (other synthetic voices) and 0.67-0.82
  // (eight short real recordings); another text 0.78-0.89. Above this the alignment is
  // refused, above `doubtful_match_ratio` kept with a warning: a wrong transcript is caught
  // only when far off (docs/speech.md); recordings with no speech are refused before.
  double max_match_ratio = 0.93;
  double doubtful_match_ratio = 0.85;
  // Voiced frames inside an aligned pause that add up to this much (runs closer than
  // `uncovered_gap_s` joined) are reported as speech the transcript does not cover.
  double uncovered_min_s = 0.3;
  double uncovered_gap_s = 0.15;
};

struct Alignment {
  std::vector<RawPhoneme> phonemes;  // in recording time, contiguous, from 0 to its end
  double match_ratio = 0.0;          // see AlignmentOptions::max_match_ratio
  std::string reference_voice;       // the voice (with variant) the recording matched best
  // Spans of the recording (start, end s) where it speaks but the alignment put a pause:
  // words the transcript leaves out, most likely.
  std::vector<std::pair<double, double>> uncovered_speech;
};

// Throws InputError for a recording that matches none of the references. A recording with
// no speech in it should be refused before (speech_presence.hpp): it is not checked here.
// `clean_text` carries no emotion markup; text positions refer to it.
Alignment align_transcript(const Audio& recording, const std::string& clean_text,
                           const AlignmentOptions& options);

// The warping itself, for a reference whose phoneme times are known: what align_transcript
// does after synthesis (tests use it with references of their own).
Alignment align_reference(const Audio& recording, const Audio& reference,
                          const std::vector<RawPhoneme>& reference_phonemes,
                          const AlignmentOptions& options);

}  // namespace rostro::speech
