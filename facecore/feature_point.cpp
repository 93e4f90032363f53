#include "facecore/feature_point.hpp"

#include <array>
#include <charconv>

namespace rostro {
namespace {

constexpr std::array<FeaturePointInfo, kFeaturePointCount> kPoints = {{
    {{2, 1}, "bottom of the chin"},
    {{2, 2}, "middle point of the inner upper lip contour"},
    {{2, 3}, "middle point of the inner lower lip contour"},
    {{2, 4}, "left corner of the inner lip contour"},
    {{2, 5}, "right corner of the inner lip contour"},
    {{2, 6}, "midpoint between 2.2 and 2.4 on the inner upper lip contour"},
    {{2, 7}, "midpoint between 2.2 and 2.5 on the inner upper lip contour"},
    {{2, 8}, "midpoint between 2.3 and 2.4 on the inner lower lip contour"},
    {{2, 9}, "midpoint between 2.3 and 2.5 on the inner lower lip contour"},
    {{2, 10}, "chin boss"},
    {{2, 11}, "chin left corner"},
    {{2, 12}, "chin right corner"},
    {{2, 13}, "left corner of the jaw bone"},
    {{2, 14}, "right corner of the jaw bone"},
    {{3, 1}, "centre of the upper inner left eyelid"},
    {{3, 2}, "centre of the upper inner right eyelid"},
    {{3, 3}, "centre of the lower inner left eyelid"},
    {{3, 4}, "centre of the lower inner right eyelid"},
    {{3, 5}, "centre of the pupil of the left eye"},
    {{3, 6}, "centre of the pupil of the right eye"},
    {{3, 7}, "outer corner of the left eye"},
    {{3, 8}, "inner corner of the right eye"},
    {{3, 9}, "centre of the lower outer left eyelid"},
    {{3, 10}, "centre of the lower outer right eyelid"},
    {{3, 11}, "inner corner of the left eye"},
    {{3, 12}, "outer corner of the right eye"},
    {{3, 13}, "centre of the upper outer left eyelid"},
    {{3, 14}, "centre of the upper outer right eyelid"},
    {{4, 1}, "inner corner of the left eyebrow"},
    {{4, 2}, "inner corner of the right eyebrow"},
    {{4, 3}, "uppermost point of the left eyebrow"},
    {{4, 4}, "uppermost point of the right eyebrow"},
    {{4, 5}, "outer corner of the left eyebrow"},
    {{4, 6}, "outer corner of the right eyebrow"},
    {{5, 1}, "centre of the left cheek"},
    {{5, 2}, "centre of the right cheek"},
    {{5, 3}, "left cheek bone"},
    {{5, 4}, "right cheek bone"},
    {{6, 1}, "tip of the tongue"},
    {{6, 2}, "centre of the tongue body"},
    {{6, 3}, "left border of the tongue"},
    {{6, 4}, "right border of the tongue"},
    {{7, 1}, "top of the spine (centre of head rotation)"},
    {{8, 1}, "middle point of the outer upper lip contour"},
    {{8, 2}, "middle point of the outer lower lip contour"},
    {{8, 3}, "left corner of the outer lip contour"},
    {{8, 4}, "right corner of the outer lip contour"},
    {{8, 5}, "midpoint between 8.3 and 8.1 on the outer upper lip contour"},
    {{8, 6}, "midpoint between 8.4 and 8.1 on the outer upper lip contour"},
    {{8, 7}, "midpoint between 8.3 and 8.2 on the outer lower lip contour"},
    {{8, 8}, "midpoint between 8.4 and 8.2 on the outer lower lip contour"},
    {{8, 9}, "right high point of the Cupid's bow"},
    {{8, 10}, "left high point of the Cupid's bow"},
    {{9, 1}, "left nostril border"},
    {{9, 2}, "right nostril border"},
    {{9, 3}, "nose tip"},
    {{9, 4}, "bottom right edge of the nose"},
    {{9, 5}, "bottom left edge of the nose"},
    {{9, 6}, "right upper edge of the nose bone"},
    {{9, 7}, "left upper edge of the nose bone"},
    {{9, 8}, "top of the upper teeth"},
    {{9, 9}, "bottom of the lower teeth"},
    {{9, 10}, "bottom of the upper teeth"},
    {{9, 11}, "top of the lower teeth"},
    {{9, 12}, "middle lower edge of the nose bone"},
    {{9, 13}, "left lower edge of the nose bone"},
    {{9, 14}, "right lower edge of the nose bone"},
    {{9, 15}, "bottom middle edge of the nose"},
    {{10, 1}, "top of the left ear"},
    {{10, 2}, "top of the right ear"},
    {{10, 3}, "back of the left ear"},
    {{10, 4}, "back of the right ear"},
    {{10, 5}, "bottom of the left ear lobe"},
    {{10, 6}, "bottom of the right ear lobe"},
    {{10, 7}, "lower contact point between the left ear lobe and the face"},
    {{10, 8}, "lower contact point between the right ear lobe and the face"},
    {{10, 9}, "upper contact point between the left ear and the face"},
    {{10, 10}, "upper contact point between the right ear and the face"},
    {{11, 1}, "middle border between hair and forehead"},
    {{11, 2}, "right border between hair and forehead"},
    {{11, 3}, "left border between hair and forehead"},
    {{11, 4}, "top of the skull"},
    {{11, 5}, "hair thickness over 11.4"},
    {{11, 6}, "back of the skull"},
}};

bool parse_int(std::string_view text, int& out) {
  if (text.empty()) return false;
  auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), out);
  return ec == std::errc() && end == text.data() + text.size();
}

}  // namespace

std::string FeaturePointId::str() const {
  return std::to_string(group) + "." + std::to_string(index);
}

std::span<const FeaturePointInfo> feature_point_table() {
  return kPoints;
}

bool is_eyelid_midpoint(FeaturePointId id) {
  return id.group == 3 && id.index >= 1 && id.index <= 4;
}

bool is_feature_point(FeaturePointId id) {
  for (const FeaturePointInfo& p : kPoints)
    if (p.id == id) return true;
  return false;
}

std::optional<FeaturePointId> parse_feature_point(std::string_view text) {
  const auto dot = text.find('.');
  if (dot == std::string_view::npos) return std::nullopt;
  FeaturePointId id;
  if (!parse_int(text.substr(0, dot), id.group) || !parse_int(text.substr(dot + 1), id.index))
    return std::nullopt;
  if (!is_feature_point(id)) return std::nullopt;
  return id;
}

FeaturePointId mirror(FeaturePointId id) {
  // Left/right twins as the standard numbers them; a point in no pair is on the mid-line.
  static constexpr std::array<std::array<FeaturePointId, 2>, 32> kPairs = {{
      {{{2, 4}, {2, 5}}},   {{{2, 6}, {2, 7}}},   {{{2, 8}, {2, 9}}},    {{{2, 11}, {2, 12}}},
      {{{2, 13}, {2, 14}}}, {{{3, 1}, {3, 2}}},   {{{3, 3}, {3, 4}}},    {{{3, 5}, {3, 6}}},
      {{{3, 7}, {3, 12}}},  {{{3, 11}, {3, 8}}},  {{{3, 9}, {3, 10}}},   {{{3, 13}, {3, 14}}},
      {{{4, 1}, {4, 2}}},   {{{4, 3}, {4, 4}}},   {{{4, 5}, {4, 6}}},    {{{5, 1}, {5, 2}}},
      {{{5, 3}, {5, 4}}},   {{{6, 3}, {6, 4}}},   {{{8, 3}, {8, 4}}},    {{{8, 5}, {8, 6}}},
      {{{8, 7}, {8, 8}}},   {{{8, 10}, {8, 9}}},  {{{9, 1}, {9, 2}}},    {{{9, 5}, {9, 4}}},
      {{{9, 7}, {9, 6}}},   {{{9, 13}, {9, 14}}}, {{{10, 1}, {10, 2}}},  {{{10, 3}, {10, 4}}},
      {{{10, 5}, {10, 6}}}, {{{10, 7}, {10, 8}}}, {{{10, 9}, {10, 10}}}, {{{11, 3}, {11, 2}}},
  }};
  for (const auto& pair : kPairs) {
    if (pair[0] == id) return pair[1];
    if (pair[1] == id) return pair[0];
  }
  return id;
}

}  // namespace rostro
