#pragma once
// Builds phoneme lists by hand for the planner tests: (symbol, class, viseme, duration ms).

#include <string>
#include <vector>

#include "speech/phoneme.hpp"

namespace rostro::speech::test {

struct Spec {
  std::string symbol;
  char cls;  // 'v' vowel, 'c' consonant, 's' silence
  int viseme;
  double ms;
};

// Contiguous phonemes from time 0; one word between silences.
inline std::vector<Phoneme> phonemes(const std::vector<Spec>& specs) {
  std::vector<Phoneme> out;
  double t = 0.0;
  int word = 0;
  bool in_word = false;
  for (const Spec& s : specs) {
    Phoneme p;
    p.symbol = s.symbol;
    p.cls = s.cls == 'v'   ? PhonemeClass::Vowel
            : s.cls == 'c' ? PhonemeClass::Consonant
                           : PhonemeClass::Silence;
    p.viseme = s.viseme;
    p.start_s = t;
    t += s.ms / 1000.0;
    p.end_s = t;
    p.closes_lips = p.cls == PhonemeClass::Consonant && s.viseme == 1;
    if (p.cls == PhonemeClass::Silence) {
      if (in_word) ++word;
      in_word = false;
      p.word = -1;
    } else {
      in_word = true;
      p.word = word;
    }
    out.push_back(p);
  }
  return out;
}

// "affluence" #: { f l u @ n s #: with the durations of seed003 4.2 (ms).
inline std::vector<Phoneme> affluence() {
  return phonemes({{"#:", 's', 0, 200},
                   {"{", 'v', 10, 120},
                   {"f", 'c', 2, 100},
                   {"l", 'c', 8, 60},
                   {"u", 'v', 14, 110},
                   {"@", 'v', 11, 60},
                   {"n", 'c', 8, 70},
                   {"s", 'c', 7, 120},
                   {"#:", 's', 0, 200}});
}

// "street" #: s t r i: t #: with the durations of seed003 4.4 (ms).
inline std::vector<Phoneme> street() {
  return phonemes({{"#:", 's', 0, 200},
                   {"s", 'c', 7, 100},
                   {"t", 'c', 4, 50},
                   {"r", 'c', 9, 60},
                   {"i:", 'v', 12, 150},
                   {"t", 'c', 4, 80},
                   {"#:", 's', 0, 200}});
}

}  // namespace rostro::speech::test
