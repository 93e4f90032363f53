#pragma once
// An image pyramid for OpenCV's pyramidal Lucas-Kanade whose derivative images are filled in
// only where LK will read them.
//
// cv::calcOpticalFlowPyrLK reads the first image's Scharr derivatives only in the window
// around each point it follows (the template stays at the point; only the second image is
// sampled where the point moves). cv::buildOpticalFlowPyramid computes them over every
// pixel of every level, which on a 1280x720 face is most of the pyramid's cost. Here the
// levels are built without derivatives and derivatives() fills the windows around the points
// about to be followed from this pyramid, with the same Scharr filter and scale as OpenCV's,
// into buffers kept from frame to frame, each pixel once per build. as_lk_input() is the
// interleaved image/derivative layout calcOpticalFlowPyrLK accepts as a ready-made pyramid.

#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

namespace rostro::tracking {

class LkPyramid {
 public:
  // Levels of `image` (8-bit grey) up to `levels` above it, bordered for `window`; copies the
  // pixels (the input may change afterwards). Derivatives are stale until derivatives().
  void build(const cv::Mat& image, cv::Size window, int levels);
  // Fills the derivatives LK reads when following `points` (level-0 pixels of this pyramid).
  void derivatives(const std::vector<cv::Point2f>& points);
  const std::vector<cv::Mat>& as_lk_input() const { return interleaved_; }
  int levels() const { return static_cast<int>(images_.size()) - 1; }
  cv::Size size() const { return images_.empty() ? cv::Size() : images_[0].size(); }

 private:
  cv::Size window_;
  std::vector<cv::Mat> images_;       // bordered ROIs, as buildOpticalFlowPyramid gives them
  std::vector<cv::Mat> derivatives_;  // CV_16SC2 (dx, dy) ROIs of zero-bordered buffers
  std::vector<cv::Mat> interleaved_;
  // Per level, a bit per pixel set where the derivatives are up to date (rows of words()).
  std::vector<std::vector<uint64_t>> filled_;
  static size_t words(int width) { return (static_cast<size_t>(width) + 63) / 64; }
};

}  // namespace rostro::tracking
