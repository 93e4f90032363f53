#include "speech/key_shapes.hpp"

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>

#include "facecore/data_path.hpp"
#include "facecore/error.hpp"
#include "facecore/json_file.hpp"

namespace rostro::speech {

FapVector low_level_vector(const FapFrame& frame) {
  FapVector v{};
  for (int id = 3; id <= kFapCount; ++id) fap(v, id) = frame.get(id);
  return v;
}

KeyShapes::KeyShapes(const ExpressionLibrary& library, const std::filesystem::path& path) {
  for (int i = 0; i < kVisemeCount; ++i)
    visemes_[static_cast<std::size_t>(i)] = low_level_vector(library.viseme(i));
  const nlohmann::json j = read_json_file(path, "the key shape file");
  const auto id_of = [&](const std::string& name) {
    const auto id = find_fap(name);
    if (!id) throw InputError(where(path.string(), 0, "unknown FAP name '" + name + "'"));
    return *id;
  };
  vowel_weight_ = j.value("vowel_weight", 0.4);
  closure_tolerance_ = j.value("closure_tolerance", 5.0);
  if (vowel_weight_ < 0.0 || vowel_weight_ > 1.0)
    throw InputError(where(path.string(), 0, "vowel_weight must be in 0..1"));
  for (const auto& pair : j.at("lip_pairs")) {
    const int top = id_of(pair.at(0).get<std::string>());
    const int bottom = id_of(pair.at(1).get<std::string>());
    lip_pairs_.emplace_back(top, bottom);
    closure_faps_.push_back(top);
    closure_faps_.push_back(bottom);
  }
  closure_faps_.push_back(3);  // open_jaw opens every pair
  std::sort(closure_faps_.begin(), closure_faps_.end());
  for (const auto& [viseme, names] : j.at("locks").items()) {
    const int v = std::stoi(viseme);
    if (v < 0 || v >= kVisemeCount)
      throw InputError(where(path.string(), 0, "lock for unknown viseme " + viseme));
    for (const auto& name : names)
      locks_[static_cast<std::size_t>(v)].push_back(id_of(name.get<std::string>()));
  }
  for (int id = 3; id <= kFapCount; ++id)
    for (const auto& vis : visemes_)
      if (fap(vis, id) != 0.0) {
        viseme_faps_.push_back(id);
        break;
      }
}

KeyShapes KeyShapes::load_default(const ExpressionLibrary& library) {
  return KeyShapes(library, data_file("speech/key_shapes.json"));
}

FapVector KeyShapes::shape(const Key& key, const std::vector<Phoneme>& p) const {
  const auto vis = [&](int i) { return p[static_cast<std::size_t>(i)].viseme; };
  switch (key.kind) {
    case KeyKind::Neutral:
      return FapVector{};
    case KeyKind::Vowel:
      return viseme(vis(key.vowel));
    case KeyKind::Consonant:
      return viseme(vis(key.consonant));
    case KeyKind::ConsonantVowel:
    case KeyKind::VowelConsonant: {
      // The consonant in its vowel context; the consonant's own articulation stays put.
      const int c = vis(key.consonant);
      const FapVector& cv = viseme(c);
      const FapVector& vv = viseme(vis(key.vowel));
      FapVector out{};
      for (std::size_t i = 0; i < out.size(); ++i) out[i] = cv[i] + vowel_weight_ * (vv[i] - cv[i]);
      for (int id : locks_[static_cast<std::size_t>(c)]) fap(out, id) = fap(cv, id);
      return out;
    }
  }
  return FapVector{};
}

double KeyShapes::lip_gap(const FapVector& v) const {
  // Assumes the lower lip rides fully on the jaw: the conservative reading of open_jaw.
  double gap = -1e9;
  for (const auto& [top, bottom] : lip_pairs_)
    gap = std::max(gap, fap(v, 3) - fap(v, top) - fap(v, bottom));
  return gap;
}

}  // namespace rostro::speech
