#include "tracking/lid_geometry.hpp"

#include <cmath>

#include "facecore/option_check.hpp"
#include "tracking/affine2d.hpp"

namespace rostro::tracking {
namespace {

// MPEG-4 3.x: the eye corners' indices.
constexpr int kRightInnerCorner = 8, kLeftInnerCorner = 11, kLeftOuterCorner = 7,
              kRightOuterCorner = 12;

double cross(cv::Point2d a, cv::Point2d b) {
  return a.x * b.y - a.y * b.x;
}

}  // namespace

void EyeOptions::validate() const {
  OptionCheck("EyeOptions")
      .at_least("inner_corner_max_elongation_large", inner_corner_max_elongation_large, 1)
      .not_negative("lid_sideways_fraction", lid_sideways_fraction)
      .not_negative("lid_overshoot_fraction", lid_overshoot_fraction)
      .positive("lid_reach", lid_reach)
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

std::optional<LidGeometry::LineOffset> LidGeometry::offset_from_corner_line(
    size_t i, const std::vector<cv::Point2d>& start, cv::Point2d at, cv::Point2d inner,
    cv::Point2d outer) const {
  if (!corners_[i]) return std::nullopt;
  const auto [start_inner, start_outer] = *corners_[i];
  const cv::Point2d line = outer - inner;
  const cv::Point2d start_line = start[start_outer] - start[start_inner];
  const double length = cv::norm(line), start_length = cv::norm(start_line);
  if (length <= 0 || start_length <= 0) return std::nullopt;
  // Signed distances from the line, positive on the side the dot was at the start.
  const double at_start = cross(start_line, start[i] - start[start_inner]) / start_length;
  LineOffset o;
  o.now = cross(line, at - inner) / length * (at_start > 0 ? 1 : -1);
  o.at_start = std::abs(at_start);
  return o;
}

}  // namespace internal
}  // namespace rostro::tracking
