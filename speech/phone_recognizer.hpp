#pragma once
// Recognition for a recorded voice without a transcript (English only): PocketSphinx's
// phonetic decoder (all-phone search with the en-us acoustic model and phone language
// model, as Rhubarb Lip Sync does) gives timed ARPAbet phones, renamed to the espeak-ng
// symbols of data/speech/en.json so the same animation rules apply.

#include <filesystem>
#include <string>
#include <vector>

#include "speech/audio.hpp"
#include "speech/phoneme.hpp"

namespace rostro::speech {

struct PhoneRecognizerOptions {
  // Debian's pocketsphinx-en-us package.
  std::filesystem::path model_dir = "/usr/share/pocketsphinx/model/en-us";
};

// The espeak-ng English symbol for an ARPAbet phone ("AA" -> "A:"), "_" for silence and
// fillers, empty when unknown.
std::string espeak_symbol_for_arpabet(const std::string& phone);

// Timed phonemes covering the whole recording. Throws InputError when the model is not
// installed, and std::runtime_error when PocketSphinx fails.
std::vector<RawPhoneme> recognize_phones(const Audio& recording,
                                         const PhoneRecognizerOptions& options = {});

}  // namespace rostro::speech
