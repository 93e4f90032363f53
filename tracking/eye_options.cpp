#include "tracking/eye_options.hpp"

#include "facecore/option_check.hpp"

namespace rostro::tracking {
namespace {

// MPEG-4 3.x: the inner eye corners' indices.
constexpr int kRightInnerCorner = 8, kLeftInnerCorner = 11;

}  // namespace

void EyeOptions::validate() const {
  OptionCheck("EyeOptions")
      .at_least("inner_corner_max_elongation_large", inner_corner_max_elongation_large, 1)
      .at_least("max_dot_growth_found", max_dot_growth_found, 1)
      .not_negative("eye_size_memory_frames", eye_size_memory_frames)
      .at_least("edge_on_elongation", edge_on_elongation, 1)
      .at_least("max_lid_elongation", max_lid_elongation, 1);
}

namespace internal {

bool is_eye_point(const FeaturePointId& fp) {
  return fp.group == 3;
}

bool is_inner_eye_corner(const FeaturePointId& fp) {
  return fp.group == 3 && (fp.index == kRightInnerCorner || fp.index == kLeftInnerCorner);
}

}  // namespace internal
}  // namespace rostro::tracking
