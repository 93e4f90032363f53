#pragma once
// MPEG-4 facial definition (feature) points "2.1" .. "11.6", 84 in all
// (shared/reference/mpeg4_fdp_points.csv).

#include <compare>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace rostro {

struct FeaturePointId {
  int group = 0;  // 2..11
  int index = 0;  // 1..

  auto operator<=>(const FeaturePointId&) const = default;
  std::string str() const;
};

struct FeaturePointInfo {
  FeaturePointId id;
  std::string_view description;
};

inline constexpr int kFeaturePointCount = 84;

std::span<const FeaturePointInfo> feature_point_table();
bool is_feature_point(FeaturePointId id);

// Parses "3.5"; nullopt for text that is not one of the 84 points.
std::optional<FeaturePointId> parse_feature_point(std::string_view text);

// MPEG-4 3.1-3.4: the midpoints of the upper and lower eyelids' margins (odd: the left eye).
bool is_eyelid_midpoint(FeaturePointId id);

// The face-symmetric twin ("3.5" <-> "3.6"), or the point itself on the mid-line.
FeaturePointId mirror(FeaturePointId id);

}  // namespace rostro
