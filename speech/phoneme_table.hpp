#pragma once
// Animation rules, part 1: a language's phoneme table (data/speech/<lang>.json) classifies
// each synthesiser phoneme (vowel, consonant, silence) and maps it to an MPEG-4 viseme.
// Diphthongs are split into their parts (seed003, Fig 10); unknown phonemes are kept in the
// timeline and reported, never silently dropped.

#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "speech/phoneme.hpp"

namespace rostro::speech {

struct PhonemeInfo {
  PhonemeClass cls = PhonemeClass::Consonant;
  int viseme = 0;
  bool closes_lips = false;
  bool modifier = false;           // joins the previous phoneme (espeak-ng ';')
  std::vector<std::string> split;  // parts of a diphthong, each an equal share
};

class LanguageTable {
 public:
  // Throws InputError naming the file and entry for a malformed table.
  static LanguageTable load(const std::filesystem::path& path);
  // data/speech/<base>.json for a language or voice code: es, es-419 -> es; pt, pt-br -> pt.
  static LanguageTable for_language(std::string_view language);
  static std::string base_language(std::string_view language);

  const std::string& language() const { return language_; }
  const std::string& default_voice() const { return default_voice_; }
  // Follows aliases; nullptr when the symbol is not in the table.
  const PhonemeInfo* find(std::string_view symbol) const;
  std::vector<std::string> symbols() const;

 private:
  std::string language_;
  std::string default_voice_;
  std::map<std::string, PhonemeInfo, std::less<>> entries_;
  std::map<std::string, std::string, std::less<>> aliases_;
};

struct UnknownPhoneme {
  std::string symbol;
  double start_s = 0.0;
};

struct Resolution {
  std::vector<Phoneme> phonemes;        // contiguous, consecutive silences merged
  std::vector<UnknownPhoneme> unknown;  // kept in `phonemes` as neutral consonants
};

// Applies the table: words from the synthesiser's text positions (or from silences when
// there are none), modifiers joined to their phoneme, diphthongs split.
Resolution resolve(const std::vector<RawPhoneme>& raw, const LanguageTable& table);

// "X at 1.23 s, Y at 2.00 s" for a warning; empty when there is nothing to report.
std::string describe_unknown(const std::vector<UnknownPhoneme>& unknown,
                             std::size_t max_listed = 8);

}  // namespace rostro::speech
