#include "tracking/lid_geometry.hpp"

#include <cmath>

#include "facecore/option_check.hpp"
#include "tracking/affine2d.hpp"

namespace rostro::tracking {
namespace {

// MPEG-4 3.x: the eye corners' indices.
constexpr int kRightInnerCorner = 8, kLeftInnerCorner = 11, kLeftOuterCorner = 7,
              kRightOuterCorner = 12;

}  // namespace

void EyeOptions::validate() const {
  OptionCheck("EyeOptions")
      .at_least("inner_corner_max_elongation_large", inner_corner_max_elongation_large, 1)
      .not_negative("lid_sideways_fraction", lid_sideways_fraction)
      .at_least("max_dot_growth_found", max_dot_growth_found, 1)
      .not_negative("eye_size_memory_frames", eye_size_memory_frames)
      .at_least("edge_on_elongation", edge_on_elongation, 1)
      .at_least("max_lid_elongation", max_lid_elongation, 1);
}

namespace internal {

bool is_eye_point(const FeaturePointId& fp) {
  return fp.group == 3;
}

bool is_lid_point(const FeaturePointId& fp) {
  return is_eyelid_midpoint(fp);
}

bool is_inner_eye_corner(const FeaturePointId& fp) {
  return fp.group == 3 && (fp.index == kRightInnerCorner || fp.index == kLeftInnerCorner);
}

LidGeometry::LidGeometry(const std::vector<FeaturePointId>& points) {
  corners_.assign(points.size(), std::nullopt);
  for (size_t i = 0; i < points.size(); ++i) {
    if (!is_lid_point(points[i])) continue;
    const bool left = points[i].index % 2 == 1;
    std::optional<size_t> inner, outer;
    for (size_t j = 0; j < points.size(); ++j) {
      const FeaturePointId& fp = points[j];
      if (fp.group != 3) continue;
      if (fp.index == (left ? kLeftInnerCorner : kRightInnerCorner)) inner = j;
      if (fp.index == (left ? kLeftOuterCorner : kRightOuterCorner)) outer = j;
    }
    if (inner && outer) corners_[i] = std::pair{*inner, *outer};
  }
}

std::optional<cv::Point2d> LidGeometry::axis(size_t i, const std::vector<cv::Point2d>& start,
                                             const cv::Matx23d& start_to_now) const {
  if (!corners_[i]) return std::nullopt;
  const auto [inner, outer] = *corners_[i];
  const cv::Point2d axis = apply_linear(start_to_now, start[outer] - start[inner]);
  const double length = cv::norm(axis);
  if (length <= 0) return std::nullopt;
  return axis * (1.0 / length);
}

}  // namespace internal
}  // namespace rostro::tracking
