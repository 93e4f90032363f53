#pragma once
// Timed phonemes: what recognition (espeak-ng or an MBROLA .pho file) hands to the
// animation rules. Times are seconds from the first audio sample: the audio clock.

#include <string>
#include <vector>

namespace rostro::speech {

// A phoneme as the synthesiser reported it, before any language table is applied.
struct RawPhoneme {
  std::string symbol;      // espeak-ng (or .pho) phoneme name, e.g. "a", "tS", "_:"
  double start_s = 0.0;    // start in audio time
  double end_s = 0.0;      // end in audio time
  int text_position = -1;  // character index (0-based, code points) of its word, -1 unknown
};

enum class PhonemeClass { Vowel, Consonant, Silence };

// A phoneme after the language table: classified and mapped to an MPEG-4 viseme.
struct Phoneme {
  std::string symbol;
  PhonemeClass cls = PhonemeClass::Silence;
  int viseme = 0;  // MPEG-4 viseme 0..14
  double start_s = 0.0;
  double end_s = 0.0;
  int word = -1;             // word number, -1 for silences and when unknown
  bool closes_lips = false;  // bilabial: must close the lips in at least one frame
  bool known = true;         // false when the language table did not know the symbol

  double duration() const { return end_s - start_s; }
};

std::string_view class_name(PhonemeClass cls);

}  // namespace rostro::speech
