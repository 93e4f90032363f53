#pragma once
// Image points through 2x3 affine transforms (cv::Matx23d): the small helpers the tracking
// library's files share (internal to the library).

#include <cmath>
#include <opencv2/core.hpp>

namespace rostro::tracking {

// The point `p` taken through `m`.
inline cv::Point2d apply(const cv::Matx23d& m, cv::Point2d p) {
  return {m(0, 0) * p.x + m(0, 1) * p.y + m(0, 2), m(1, 0) * p.x + m(1, 1) * p.y + m(1, 2)};
}

// The offset (a difference of points) `d` taken through `m`'s linear part: no shift.
inline cv::Point2d apply_linear(const cv::Matx23d& m, cv::Point2d d) {
  return {m(0, 0) * d.x + m(0, 1) * d.y, m(1, 0) * d.x + m(1, 1) * d.y};
}

// How much `m` enlarges lengths: the square root of its linear part's area factor.
inline double scale_of(const cv::Matx23d& m) {
  return std::sqrt(std::abs(m(0, 0) * m(1, 1) - m(0, 1) * m(1, 0)));
}

}  // namespace rostro::tracking
