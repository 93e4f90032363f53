#pragma once
// Animation rules, part 3: the mouth shape (a low-level FAP vector) of each planner key,
// built from the MPEG-4 viseme library (facecore ExpressionLibrary, data/visemes.json) and
// data/speech/key_shapes.json. Also the "lips closed" test used for bilabials.

#include <array>
#include <filesystem>
#include <vector>

#include "facecore/expression_library.hpp"
#include "speech/coarticulation.hpp"
#include "speech/phoneme.hpp"

namespace rostro::speech {

using FapVector = std::array<double, kFapCount>;  // [id - 1], each FAP in its own unit

inline double& fap(FapVector& v, int id) {
  return v[static_cast<std::size_t>(id - 1)];
}
inline double fap(const FapVector& v, int id) {
  return v[static_cast<std::size_t>(id - 1)];
}

FapVector low_level_vector(const FapFrame& frame);

class KeyShapes {
 public:
  // Throws InputError naming the file for a malformed key_shapes.json.
  KeyShapes(const ExpressionLibrary& library, const std::filesystem::path& key_shapes_json);
  static KeyShapes load_default(const ExpressionLibrary& library);

  const FapVector& viseme(int index) const { return visemes_.at(static_cast<std::size_t>(index)); }
  FapVector shape(const Key& key, const std::vector<Phoneme>& phonemes) const;

  // Largest vertical gap between the lips (MNS units; <= 0 touching or pressed).
  double lip_gap(const FapVector& v) const;
  bool lips_closed(const FapVector& v) const { return lip_gap(v) <= closure_tolerance_; }
  double closure_tolerance() const { return closure_tolerance_; }
  // The FAPs a lip closure fixes (jaw and vertical lip FAPs): they follow the viseme alone
  // while a bilabial closes, whatever the expression.
  const std::vector<int>& closure_faps() const { return closure_faps_; }
  // Every FAP some viseme moves.
  const std::vector<int>& viseme_faps() const { return viseme_faps_; }

 private:
  std::array<FapVector, kVisemeCount> visemes_{};
  std::array<std::vector<int>, kVisemeCount> locks_{};
  std::vector<std::pair<int, int>> lip_pairs_;
  std::vector<int> closure_faps_;
  std::vector<int> viseme_faps_;
  double vowel_weight_ = 0.4;
  double closure_tolerance_ = 5.0;
};

}  // namespace rostro::speech
