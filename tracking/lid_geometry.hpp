#pragma once
// Where a lid dot can be: the eye's dots (MPEG-4 group 3) told apart, each lid dot's eye
// corners found in the layout, and a point's place relative to the line through those corners.
// The tracker uses it to keep a lid dot off the brow's, the other lid's and a corner's dot
// (internal to the tracking library).

#include <cstddef>
#include <opencv2/core.hpp>
#include <optional>
#include <utility>
#include <vector>

#include "facecore/feature_point.hpp"

namespace rostro::tracking {

// MPEG-4 group 3: the lids and the eye corners.
bool is_eye_point(const FeaturePointId& fp);
// MPEG-4 3.1-3.4: the upper and lower lids' midpoints (odd: the face's left eye).
bool is_lid_point(const FeaturePointId& fp);
// MPEG-4 3.8, 3.11: the inner eye corners.
bool is_inner_eye_corner(const FeaturePointId& fp);

class LidGeometry {
 public:
  LidGeometry() = default;
  // `points[i]`: marker i's feature point, in the tracker's marker order. Below, `start[i]` is
  // marker i's position at the start of tracking, in the same order.
  explicit LidGeometry(const std::vector<FeaturePointId>& points);

  // Lid dot i's eye corners (inner, outer) as marker indices; empty for other markers and
  // when a corner of that eye has no marker (MPEG-4 3.11/3.7 left, 3.8/3.12 right).
  const std::optional<std::pair<size_t, size_t>>& corners(size_t i) const { return corners_[i]; }

  // The image direction of lid dot i's eye from its inner to its outer corner, as
  // `start_to_now` maps the start positions; empty without corners.
  std::optional<cv::Point2d> axis(size_t i, const std::vector<cv::Point2d>& start,
                                  const cv::Matx23d& start_to_now) const;

  // How far `at` lies from the line through the eye's corners now (`inner`, `outer`), positive
  // on the side lid dot i was at the start, and how far the dot was from it then (positive);
  // empty without corners or when either line has no length.
  struct LineOffset {
    double now = 0;
    double at_start = 0;
  };
  std::optional<LineOffset> offset_from_corner_line(size_t i, const std::vector<cv::Point2d>& start,
                                                    cv::Point2d at, cv::Point2d inner,
                                                    cv::Point2d outer) const;

 private:
  std::vector<std::optional<std::pair<size_t, size_t>>> corners_;
};

}  // namespace rostro::tracking
