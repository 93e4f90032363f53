#pragma once
// The centre of a dot's darkest core: for a dot merged with a dark feature nearly as dark as its
// ink (an inner brow dot and the eyebrow's end), where even the detector's highest share of the
// contrast (0.9) takes in the feature. The ink is still darker than the feature: the pixels
// within a small tolerance of the darkest near the dot are the dot's own.
//
// The closer the feature's darkest to the ink, the more the core leans toward it, though far
// less than the merged blob's centre, which lies out along the eyebrow
// (tests/tracking/brow_merge_test.cpp bounds both; docs/rules.md measures the rules below on
// and off).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "facecore/option_check.hpp"

namespace rostro::tracking {

// The brow dots' rules (MPEG-4 4.1-4.4), TrackerOptions::brows.
struct BrowOptions {
  // The edge-fitted centre for the mid-brow dots (4.3, 4.4) too. They sit on the eyebrow, a
  // band lighter than the ink that the brow's raise moves against the dot: the centroid is
  // pulled toward the band's larger side, the edge fit much less (docs/rules.md).
  bool edge_fit_mid_brows = true;
  // An inner brow dot (4.1, 4.2) sits at the eyebrow's end. Where the eyebrow (nearly as dark
  // as the ink) touches it, the two merge at every share of the dot's contrast and the blob's
  // centre, and its edge, lie out along the eyebrow, most under head turns. Such a blob
  // (measured above half its contrast, and still not at 0.9, or long or ragged there) does not
  // place the dot by its centre (tests/tracking/brow_merge_test.cpp). false: the blob's centre.
  bool hold_merged_inner_brows = true;
  // Such a dot is placed at the centre of its ink's core (ink_core_centre() below): the pixels
  // within this share of its contrast of the darkest within 0.7 of its width of where LK moved it
  // (of the merged blob's centre when found again after a loss, or at the start). The ink is darker
  // than the eyebrow's end. Held where LK moved it, the dot drifts: LK weighs the eyebrow in its
  // window, and each frame's pull adds to the last (docs/rules.md); a dot found again on the
  // merged blob would be held off by the blob's own error. 0: where LK moved it.
  double inner_brow_core_tolerance = 0.08;

  // Throws InputError naming the first option out of range ("BrowOptions::...").
  void validate() const {
    OptionCheck("BrowOptions").not_negative("inner_brow_core_tolerance", inner_brow_core_tolerance);
  }
};

namespace ink_core_detail {

// Above this median second difference along rows (grey levels; about 1.65 x the sensor noise's
// sigma where most of the window is flat) the core is found on 3x3 means: in noise the darkest
// single pixels are wherever the noise dips. The threshold sits between what the rendered head
// measures without noise (its shading and edges) and with the suite's low-light noise (sigma 6),
// where single pixels put the inner brow dots about twice as far off as the 3x3 means do.
constexpr double kNoisySecondDifference = 6.5;

inline bool noisy(const cv::Mat& gray, const cv::Rect& box) {
  std::vector<int> steps;
  steps.reserve(static_cast<size_t>(box.area()));
  for (int y = box.y; y < box.y + box.height; ++y) {
    const uint8_t* row = gray.ptr<uint8_t>(y);
    for (int x = box.x; x < box.x + box.width; ++x)
      steps.push_back(std::abs(row[x - 1] + row[x + 1] - 2 * row[x]));
  }
  if (steps.empty()) return false;
  auto mid = steps.begin() + static_cast<long>(steps.size() / 2);
  std::nth_element(steps.begin(), mid, steps.end());
  return *mid > kNoisySecondDifference;
}

}  // namespace ink_core_detail

// The dark (`dark` true; else bright) core's centre near `start` in `gray` (8-bit, one channel):
// the pixels within `tolerance` grey levels of the darkest inside `radius` of it, each weighted by
// the square of how far inside the tolerance it is, the disc re-centred on the core twice.
// Squared: the pixels blending the ink with the feature (darker than those blending it with skin)
// weigh little against the ink's own. In sensor noise the levels are 3x3 means. nullopt when the
// disc leaves the image.
inline std::optional<cv::Point2d> ink_core_centre(const cv::Mat& gray, cv::Point2d start,
                                                  double radius, double tolerance, bool dark) {
  CV_Assert(gray.type() == CV_8UC1);
  auto box_at = [&](cv::Point2d c) {
    const int x0 = static_cast<int>(std::floor(c.x - radius)),
              y0 = static_cast<int>(std::floor(c.y - radius));
    return cv::Rect(cv::Point(x0, y0), cv::Point(static_cast<int>(std::ceil(c.x + radius)) + 1,
                                                 static_cast<int>(std::ceil(c.y + radius)) + 1));
  };
  // One pixel of room all round for the 3x3 means and the second differences.
  const cv::Rect inside(1, 1, gray.cols - 2, gray.rows - 2);
  cv::Rect box = box_at(start);
  if ((box & inside) != box) return std::nullopt;
  const int smooth = ink_core_detail::noisy(gray, box) ? 1 : 0;
  const auto level = [&](int x, int y) {
    int sum = 0;
    for (int yy = y - smooth; yy <= y + smooth; ++yy)
      for (int xx = x - smooth; xx <= x + smooth; ++xx) sum += gray.ptr<uint8_t>(yy)[xx];
    const double v = static_cast<double>(sum) / ((2 * smooth + 1) * (2 * smooth + 1));
    return dark ? v : 255 - v;
  };

  cv::Point2d centre = start;
  for (int iteration = 0; iteration < 3; ++iteration) {
    box = box_at(centre);
    if ((box & inside) != box) return std::nullopt;
    auto in_disc = [&](int x, int y) {
      const double dx = x - centre.x, dy = y - centre.y;
      return dx * dx + dy * dy <= radius * radius;
    };
    double ink = 255;
    for (int y = box.y; y < box.y + box.height; ++y)
      for (int x = box.x; x < box.x + box.width; ++x)
        if (in_disc(x, y)) ink = std::min(ink, level(x, y));
    double sw = 0, sx = 0, sy = 0;
    for (int y = box.y; y < box.y + box.height; ++y)
      for (int x = box.x; x < box.x + box.width; ++x) {
        if (!in_disc(x, y)) continue;
        const double below = ink + tolerance - level(x, y);
        if (below <= 0) continue;
        const double w = below * below;
        sw += w, sx += w * x, sy += w * y;
      }
    if (sw <= 0) return std::nullopt;
    centre = {sx / sw, sy / sw};
  }
  return centre;
}

}  // namespace rostro::tracking
