#pragma once
// The whole speech driver in stages, like Rhubarb Lip Sync: recognition (espeak-ng, a .pho
// file, a recording aligned to its transcript, or English phones recognised in a
// recording) -> animation rules (phoneme table, coarticulation keys, key shapes) ->
// emotions, eyes and head -> FAP frames. `rostro speak` only wires options to this.

#include <filesystem>
#include <string>
#include <vector>

#include "speech/animator.hpp"
#include "speech/audio.hpp"
#include "speech/emotion_markup.hpp"
#include "speech/phoneme_table.hpp"

namespace rostro::speech {

struct SpeechRequest {
  std::string text;             // may carry emotion markup; unused with `pho`
  std::string language = "es";  // es, es-419, pt, pt-br, pt-pt, en, en-us, en-gb
  std::string voice;            // espeak-ng voice; empty: chosen from the language
  int rate_wpm = 0;
  std::filesystem::path pho;  // MBROLA .pho instead of text
  // A recording: with `pho`, its audio; with `text`, the voice reading it (aligned); alone,
  // English speech whose phones are recognised. Any format FFmpeg reads.
  std::filesystem::path audio;
};

// Where the phoneme times came from.
enum class Recognition { Synthesis, Pho, Alignment, PhoneRecognition };

// Everything the animation needs, before any frame is made.
struct PreparedSpeech {
  Audio audio;              // empty samples when a .pho came without audio
  double duration_s = 0.0;  // the audio's duration (the .pho's without audio)
  std::string voice;        // the espeak-ng voice used (the reference when aligning)
  Recognition recognition = Recognition::Synthesis;
  double match_ratio = 0.0;  // the transcript check when aligned (speech/forced_align.hpp)
  std::vector<RawPhoneme> raw;
  Resolution resolution;
  std::vector<EmotionEvent> emotions;
  std::vector<std::string> warnings;  // unknown phonemes, .pho/WAV length mismatch
};

// The espeak-ng voice for a language code: "pt" is Brazilian (pt-br), "pt-pt" European,
// "en" the table's default (en-us); a code with a region is used as given.
std::string voice_for_language(const std::string& language, const LanguageTable& table);

// When an emotion tag at clean-text position `position` takes effect: the end of the last
// word before it (seed000 find_com_time), 0 at the start.
double tag_time(std::size_t position, const std::vector<RawPhoneme>& raw,
                const LanguageTable& table);

// Recognition and rules. Throws InputError for bad markup, files, voices or recordings (a
// silent one, one that does not match its transcript, one without a transcript in a
// language other than English).
PreparedSpeech prepare_speech(const SpeechRequest& request, double default_ramp_s);

}  // namespace rostro::speech
