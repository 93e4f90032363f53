#include "speech/phoneme_table.hpp"

#include <fmt/format.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "facecore/data_path.hpp"
#include "facecore/error.hpp"
#include "facecore/json_file.hpp"

namespace rostro::speech {

std::string_view class_name(PhonemeClass cls) {
  switch (cls) {
    case PhonemeClass::Vowel:
      return "vowel";
    case PhonemeClass::Consonant:
      return "consonant";
    case PhonemeClass::Silence:
      return "silence";
  }
  return "?";
}

LanguageTable LanguageTable::load(const std::filesystem::path& path) {
  const nlohmann::json j = read_json_file(path, "the phoneme table");
  const auto bad = [&](const std::string& what) {
    return InputError(where(path.string(), 0, what));
  };
  LanguageTable t;
  t.language_ = j.value("language", "");
  t.default_voice_ = j.value("default_voice", t.language_);
  if (!j.contains("phonemes") || !j["phonemes"].is_object())
    throw bad("expected an object 'phonemes'");
  for (const auto& [symbol, e] : j["phonemes"].items()) {
    if (e.contains("alias")) {
      t.aliases_[symbol] = e["alias"].get<std::string>();
      continue;
    }
    PhonemeInfo info;
    if (e.contains("split")) {
      info.split = e["split"].get<std::vector<std::string>>();
      if (info.split.size() < 2)
        throw bad("phoneme '" + symbol + "': 'split' needs two or more parts");
      t.entries_[symbol] = info;
      continue;
    }
    const std::string cls = e.value("class", "");
    if (cls == "vowel")
      info.cls = PhonemeClass::Vowel;
    else if (cls == "consonant")
      info.cls = PhonemeClass::Consonant;
    else if (cls == "silence")
      info.cls = PhonemeClass::Silence;
    else if (cls == "modifier")
      info.modifier = true;
    else
      throw bad("phoneme '" + symbol + "': class must be vowel, consonant, silence or modifier");
    info.viseme = e.value("viseme", 0);
    if (info.viseme < 0 || info.viseme > 14)
      throw bad("phoneme '" + symbol + "': viseme must be 0..14");
    info.closes_lips =
        e.value("closes_lips", info.cls == PhonemeClass::Consonant && info.viseme == 1);
    t.entries_[symbol] = info;
  }
  // Every split part and alias target must itself be a plain phoneme of this table.
  for (const auto& [symbol, info] : t.entries_)
    for (const auto& part : info.split) {
      const PhonemeInfo* p = t.find(part);
      if (!p || !p->split.empty() || p->modifier)
        throw bad("phoneme '" + symbol + "': split part '" + part +
                  "' is not a plain phoneme of the table");
    }
  for (const auto& [alias, target] : t.aliases_)
    if (!t.entries_.count(target))
      throw bad("alias '" + alias + "' names unknown phoneme '" + target + "'");
  return t;
}

std::string LanguageTable::base_language(std::string_view language) {
  std::string base(language.substr(0, language.find_first_of("-_")));
  for (auto& c : base) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return base;
}

LanguageTable LanguageTable::for_language(std::string_view language) {
  const std::string base = base_language(language);
  if (base != "es" && base != "pt" && base != "en")
    throw InputError("no phoneme table for language '" + std::string(language) +
                     "' (expected es, pt or en)");
  return load(data_file("speech/" + base + ".json"));
}

const PhonemeInfo* LanguageTable::find(std::string_view symbol) const {
  if (auto a = aliases_.find(symbol); a != aliases_.end()) symbol = a->second;
  auto it = entries_.find(symbol);
  return it == entries_.end() ? nullptr : &it->second;
}

std::vector<std::string> LanguageTable::symbols() const {
  std::vector<std::string> out;
  for (const auto& [s, info] : entries_) out.push_back(s);
  for (const auto& [s, target] : aliases_) out.push_back(s);
  return out;
}

Resolution resolve(const std::vector<RawPhoneme>& raw, const LanguageTable& table) {
  Resolution res;
  auto& out = res.phonemes;
  int word = -1;
  int last_position = -2;
  bool after_silence = true;
  const auto push = [&](Phoneme p) {
    if (p.cls == PhonemeClass::Silence) {
      p.word = -1;
      after_silence = true;
      if (!out.empty() && out.back().cls == PhonemeClass::Silence) {  // merge #: #: (S151)
        out.back().end_s = p.end_s;
        return;
      }
    }
    out.push_back(std::move(p));
  };
  for (const RawPhoneme& r : raw) {
    const PhonemeInfo* info = table.find(r.symbol);
    if (info && info->modifier) {
      if (!out.empty()) out.back().end_s = r.end_s;  // its time belongs to its phoneme
      continue;
    }
    if (!info || info->cls != PhonemeClass::Silence) {
      // A new word when the text position changes, or (no positions: .pho) after a silence.
      const bool new_word = r.text_position >= 0 ? r.text_position != last_position : after_silence;
      if (new_word) ++word;
      last_position = r.text_position;
      after_silence = false;
    }
    if (!info) {
      res.unknown.push_back({r.symbol, r.start_s});
      Phoneme p{r.symbol, PhonemeClass::Consonant, 0, r.start_s, r.end_s, word, false, false};
      push(std::move(p));
      continue;
    }
    if (!info->split.empty()) {
      const double n = static_cast<double>(info->split.size());
      for (std::size_t k = 0; k < info->split.size(); ++k) {
        const PhonemeInfo* part = table.find(info->split[k]);
        // Absolute boundaries from the original span: the parts add up exactly.
        const double a = r.start_s + (r.end_s - r.start_s) * static_cast<double>(k) / n;
        const double b = k + 1 == info->split.size()
                             ? r.end_s
                             : r.start_s + (r.end_s - r.start_s) * static_cast<double>(k + 1) / n;
        push(Phoneme{info->split[k], part->cls, part->viseme, a, b, word, part->closes_lips, true});
      }
      continue;
    }
    push(Phoneme{r.symbol, info->cls, info->viseme, r.start_s, r.end_s, word, info->closes_lips,
                 true});
  }
  return res;
}

std::string describe_unknown(const std::vector<UnknownPhoneme>& unknown, std::size_t max_listed) {
  std::string s;
  for (std::size_t i = 0; i < unknown.size() && i < max_listed; ++i)
    s += fmt::format("{}'{}' at {:.2f} s", i ? ", " : "", unknown[i].symbol, unknown[i].start_s);
  if (unknown.size() > max_listed) s += fmt::format(" and {} more", unknown.size() - max_listed);
  return s;
}

}  // namespace rostro::speech
