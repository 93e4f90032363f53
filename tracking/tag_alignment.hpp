#pragma once
// Sub-pixel tag corners from the whole printed pattern.
//
// libapriltag's corners come from lines fitted to the black square's outer edge alone; on a tag
// 30-70 px wide they move by 0.1-0.4 px from frame to frame as the square crosses the pixel grid,
// and a tag is where the head's pose is read. Every bit cell of a tag is a known edge as well,
// so aligning the printed pattern to the image by a homography (Gauss-Newton, inverse
// compositional, with the lighting's gain and offset and their slopes across the tag) uses a few
// hundred edge pixels instead of four lines.

#include <array>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

namespace rostro::tracking {

struct TagAlignment {
  std::array<cv::Point2d, 4> corners;  // libapriltag's order (apriltag_detector.hpp)
  double blur_px;                      // the image's softness there: a Gaussian sigma, pixels
};

// One tag's pattern sampled for alignment at a given size in the image and softness.
class TagPattern {
 public:
  // `bits`: apriltag_image() of the tag (white border included), `black_width` its black
  // square's width in bit cells, `cell_px` about how many image pixels one cell spans,
  // `softness_px` the Gaussian sigma the pattern is blurred by (the camera's blur or so).
  TagPattern(const cv::Mat& bits, int black_width, double cell_px, double softness_px);

  // The corners that best align the pattern with `gray` (8-bit), starting from `corners` (a
  // pixel or so off at most). Nothing when the alignment does not converge or the image does
  // not look like the pattern there (a tag partly hidden, or not there at all). The image's
  // blur is fitted alongside, to first order: a pattern within about half a pixel of it aligns
  // unbiased.
  std::optional<TagAlignment> align(const cv::Mat& gray,
                                    const std::array<cv::Point2d, 4>& corners) const;

  double cell_px() const { return cell_px_; }
  double softness_px() const { return softness_px_; }

 private:
  static constexpr int kLighting = 7;       // the lighting model's terms (tag_alignment.cpp)
  static constexpr int kLightingLanes = 8;  // padded for the vector unit
  struct Sample {
    float x, y;   // pattern coordinates: the black square spans [-1, 1]
    float sd[8];  // its steepest-descent row: gradient times the warp's Jacobian at identity
    // The lighting model's regressors there: the pattern (0 ink to 1 paper, softened), its
    // slopes, its Laplacian (what a little more blur adds), and the offset's terms.
    float light[kLightingLanes];
    // Sets `light` from the pattern's value and Laplacian at (x, y).
    void set_lighting(float value, float laplacian);
  };

  std::vector<Sample> samples_;
  cv::Matx<double, 8, 8> hessian_inverse_;
  cv::Matx<double, kLighting, kLighting> lighting_inverse_;  // of its regressors' normal matrix
  cv::Matx<double, 8, kLighting> sd_light_;  // sum over the samples of sd x the regressors
  double cell_px_, softness_px_, px_per_sample_ = 1;
};

// One tag followed through a take: its patterns at the sizes and softness the image has asked
// for so far, built as needed and kept.
class TagAligner {
 public:
  TagAligner(cv::Mat bits, int black_width);

  // TagPattern::align with a pattern of the tag's present size, re-aligned with a softer or
  // sharper one when the image's blur is far from the pattern's. Nothing as well when a
  // corner ends up more than `max_move_px` from where it started.
  std::optional<std::array<cv::Point2d, 4>> align(const cv::Mat& gray,
                                                  const std::array<cv::Point2d, 4>& corners,
                                                  double max_move_px = 1.0);

  static constexpr double kSoftnessStep = 0.25;  // pixels between the patterns' softness
  static constexpr double kSoftestPx = 4.0;
  static constexpr double kSizeTolerance = 0.15;  // a pattern serves tags 15 % larger or smaller
  static constexpr size_t kMostPatterns = 8;

 private:
  const TagPattern& pattern(double cell_px, double softness_px);

  cv::Mat bits_;
  int black_width_;
  double softness_px_ = 0.8;  // where the first alignment starts
  std::vector<TagPattern> patterns_;
};

}  // namespace rostro::tracking
