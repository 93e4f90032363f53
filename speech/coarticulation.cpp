#include "speech/coarticulation.hpp"

namespace rostro::speech {
namespace {

bool is(const std::vector<Phoneme>& p, int i, PhonemeClass c) {
  return i >= 0 && i < static_cast<int>(p.size()) && p[static_cast<std::size_t>(i)].cls == c;
}
// Before the first phoneme there is, in effect, silence.
bool silence_or_start(const std::vector<Phoneme>& p, int i) {
  return i < 0 || is(p, i, PhonemeClass::Silence);
}

// The nearest vowel from `from` in direction `step`, staying in `word` and stopping at a
// silence: "in this word" (seed003 S163, S166, S173).
int search_vowel(const std::vector<Phoneme>& p, int from, int step, int word) {
  for (int i = from; i >= 0 && i < static_cast<int>(p.size()); i += step) {
    const Phoneme& q = p[static_cast<std::size_t>(i)];
    if (q.cls == PhonemeClass::Silence || q.word != word) return -1;
    if (q.cls == PhonemeClass::Vowel) return i;
  }
  return -1;
}

}  // namespace

std::vector<Key> plan_keys(const std::vector<Phoneme>& p, const PlannerOptions& options) {
  std::vector<Key> keys;
  if (p.empty()) return keys;
  const int n = static_cast<int>(p.size());
  const auto at = [&](int i) -> const Phoneme& { return p[static_cast<std::size_t>(i)]; };
  const auto add = [&](double t, KeyKind kind, int c, int v) {
    keys.push_back(Key{t, kind, c, v});
  };

  if (!is(p, 0, PhonemeClass::Silence)) add(at(0).start_s, KeyKind::Neutral, -1, -1);

  for (int i = 0; i < n; ++i) {
    const Phoneme& cur = at(i);
    const int prev = i - 1;
    switch (cur.cls) {
      case PhonemeClass::Silence:
        // Vowel->silence (S152) and combination->silence (S154): neutral at mid-silence.
        add(cur.start_s + cur.duration() / 2, KeyKind::Neutral, -1, -1);
        break;

      case PhonemeClass::Vowel:
        // C->V at the boundary (S148/149), unless the consonant followed a silence: then its
        // silence->CV key already sits at this boundary (S145).
        if (is(p, prev, PhonemeClass::Consonant) && !silence_or_start(p, prev - 1))
          add(cur.start_s, KeyKind::ConsonantVowel, prev, i);
        add(cur.start_s + cur.duration() / 2, KeyKind::Vowel, -1, i);  // S141/S143/S146
        break;

      case PhonemeClass::Consonant: {
        const bool has_vowel =
            search_vowel(p, i, 1, cur.word) != -1 || search_vowel(p, i, -1, cur.word) != -1;
        if (!has_vowel) {  // a vowelless word: a context-free consonant shape at its centre
          add(cur.start_s + cur.duration() / 2, KeyKind::Consonant, i, -1);
          break;
        }
        if (is(p, prev, PhonemeClass::Vowel)) {
          add(cur.start_s, KeyKind::VowelConsonant, i, prev);  // S161/S162
        } else if (is(p, prev, PhonemeClass::Consonant)) {
          if (silence_or_start(p, prev - 1) && at(prev).word == cur.word &&
              search_vowel(p, prev, 1, at(prev).word) != -1)
            break;  // word-initial cluster: the (C1,V) key is already at this boundary (fix)
          const bool prev_vowelless = search_vowel(p, prev, 1, at(prev).word) == -1 &&
                                      search_vowel(p, prev, -1, at(prev).word) == -1;
          if (prev_vowelless) {
            // The previous consonant had only its own centre key: start this word's shape here.
            const int v = search_vowel(p, i, 1, cur.word);
            if (v != -1)
              add(cur.start_s, KeyKind::ConsonantVowel, i, v);
            else
              add(cur.start_s, KeyKind::VowelConsonant, i, search_vowel(p, i, -1, cur.word));
            break;
          }
          if (const int v = search_vowel(p, i, 1, cur.word); v != -1) {
            add(cur.start_s, KeyKind::ConsonantVowel, prev, v);  // S163-S165: first C + next V
          } else if (const int w = search_vowel(p, prev, -1, at(prev).word); w != -1) {
            const int c = options.backward == BackwardConsonant::Current ? i : prev;
            add(cur.start_s, KeyKind::VowelConsonant, c, w);  // S166-S168
          } else {
            add(cur.start_s, KeyKind::Consonant, prev, -1);  // S169: no vowel either way
          }
        } else {
          // After silence: silence->CV at the end of the consonant (S170-S172).
          const int v = search_vowel(p, i, 1, cur.word);
          if (v != -1)
            add(cur.end_s, KeyKind::ConsonantVowel, i, v);
          else
            add(cur.start_s + cur.duration() / 2, KeyKind::Consonant, i, -1);  // S173 fallback
        }
        break;
      }
    }
  }
  if (!is(p, n - 1, PhonemeClass::Silence)) add(at(n - 1).end_s, KeyKind::Neutral, -1, -1);
  return keys;
}

std::string key_label(const Key& key, const std::vector<Phoneme>& p) {
  const auto sym = [&](int i) {
    return i >= 0 ? p[static_cast<std::size_t>(i)].symbol : std::string("?");
  };
  switch (key.kind) {
    case KeyKind::Neutral:
      return "#";
    case KeyKind::Vowel:
      return sym(key.vowel);
    case KeyKind::ConsonantVowel:
      return sym(key.consonant) + sym(key.vowel);
    case KeyKind::VowelConsonant:
      return sym(key.vowel) + sym(key.consonant);
    case KeyKind::Consonant:
      return sym(key.consonant);
  }
  return "?";
}

}  // namespace rostro::speech
