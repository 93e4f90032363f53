#pragma once
// Animation rules, part 2: the coarticulation planner of seed003 (CN 1214784 A, Figs 11A-D).
// A key mouth shape at each vowel centre, at each vowel/consonant and consonant/vowel
// boundary; a consonant/consonant boundary takes the first consonant with the nearest vowel
// of the word (following, else preceding with the current consonant, as the flowchart
// does); neutral at the centre of each silence. Key instants are absolute audio times, so
// nothing is rounded per interval and nothing drifts. The word-initial cluster fix of the
// notes (seed003 1.4b) is applied: "#: s t r i:" gives one (s,i:) key, not two.

#include <string>
#include <vector>

#include "speech/phoneme.hpp"

namespace rostro::speech {

enum class KeyKind {
  Neutral,         // the closed-mouth reference face (silence)
  Vowel,           // a vowel at its centre
  ConsonantVowel,  // a consonant in the context of a vowel (C->V, C->C forward, silence->CV)
  VowelConsonant,  // a vowel followed by a consonant (V->C, C->C backward)
  Consonant,       // a consonant with no vowel in its word ("hmm", "psst"): seed fallback
};

struct Key {
  double time_s = 0.0;
  KeyKind kind = KeyKind::Neutral;
  int consonant = -1;  // index into the phoneme list, -1 when none
  int vowel = -1;      // index into the phoneme list, -1 when none
  bool operator==(const Key&) const = default;
};

// Which consonant a C->C transition with only a preceding vowel uses (seed003 1.4b): the
// flowchart (step S167) pairs the vowel with the current consonant, claim 5 with the first.
enum class BackwardConsonant { Current, First };

struct PlannerOptions {
  BackwardConsonant backward = BackwardConsonant::Current;
};

// Keys in time order (equal times allowed). `phonemes` must be contiguous in time. An
// utterance that does not start (end) with silence gets a neutral key at its start (end).
std::vector<Key> plan_keys(const std::vector<Phoneme>& phonemes,
                           const PlannerOptions& options = {});

// "{f" style label for tests and debugging: vowel/consonant symbols of the key.
std::string key_label(const Key& key, const std::vector<Phoneme>& phonemes);

}  // namespace rostro::speech
