#pragma once
// The expression and viseme libraries (data/expressions.json, data/visemes.json): the FAP
// vectors behind the high-level FAPs 2 (expression) and 1 (viseme), and their expansion
// into low-level FAPs.

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "facecore/fap_frame.hpp"

namespace rostro {

inline constexpr int kExpressionCount = 7;  // 0 neutral, 1..6 the MPEG-4 expression_select
inline constexpr int kVisemeCount = 15;     // MPEG-4 visemes 0..14

class ExpressionLibrary {
 public:
  // Reads both files; throws InputError naming the file for bad JSON, an unknown FAP name,
  // a missing expression or viseme.
  static ExpressionLibrary load(const std::filesystem::path& expressions_json,
                                const std::filesystem::path& visemes_json);
  // data/expressions.json and data/visemes.json.
  static ExpressionLibrary load_default();

  // MPEG-4 expression_select numbering: 0 neutral, 1 joy, 2 sadness, 3 anger, 4 fear,
  // 5 disgust, 6 surprise.
  static std::string_view expression_name(int select);
  static std::optional<int> expression_index(std::string_view name);
  // Viseme names "sil", "p_b_m", ... for 0..14 (seed004 Appendix B).
  static std::string_view viseme_name(int index);

  // The full-intensity low-level FAP vector (mask = FAPs it sets). Throws std::out_of_range.
  const FapFrame& expression(int select) const;
  const FapFrame& viseme(int index) const;
  // Lookup by name ("joy"); nullptr when unknown.
  const FapFrame* find_expression(std::string_view name) const;

  // Replaces an entry's full-intensity low-level FAP vector (FAPs 1 and 2 are dropped).
  // Throws std::out_of_range.
  void set_expression(int select, const FapFrame& faps);
  void set_viseme(int index, const FapFrame& faps);

  // Writes both files in the format load() reads (FAPs by name; the visemes keep the
  // phoneme groups they were read with), each whole or not at all (AtomicFile). Throws
  // InputError naming the file.
  void save(const std::filesystem::path& expressions_json,
            const std::filesystem::path& visemes_json) const;

  // The expression scaled by intensity 0..1 (1 = the library vector).
  FapFrame expression_frame(int select, double intensity) const;

  // Adds the low-level FAPs that a frame's FAP 2 (select1 x intensity1/63 + select2 x
  // intensity2/63) and FAP 1 (select1 x blend/63 + select2 x (1 - blend/63)) stand for,
  // summing the two where both set a FAP. Low-level FAPs the frame already sets are never
  // overwritten. The result keeps FAPs 1 and 2 in its mask.
  FapFrame expand(const FapFrame& frame) const;

 private:
  std::array<FapFrame, kExpressionCount> expressions_{};
  std::array<FapFrame, kVisemeCount> visemes_{};
  std::array<std::string, kVisemeCount> viseme_phonemes_{};  // "p b m": kept for save()
};

}  // namespace rostro
