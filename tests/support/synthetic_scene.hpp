#pragma once
// Synthetic marker takes with exact ground truth, for the tracking tests and benchmarks: a
// textured skin-like face plane moving with a known sub-pixel similarity, the layout's dots
// drawn with exact pixel coverage (8x8 samples per pixel, so the true centre is the coverage
// centroid), AprilTags drawn from their bit patterns, mouth and brow dots moving on their own,
// optional occluders, then blur and noise.

#include <map>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "tracking/layout.hpp"

namespace rostro::tracking::testing {

struct Occluder {
  cv::Rect2d rect;           // image pixels
  int first = 0, last = -1;  // frames covered, inclusive
};

struct SceneOptions {
  cv::Size size{640, 480};
  double px_per_mm = 2.4;
  double dot_diameter_px = 8;
  double angle_deg = 0;      // in-plane head roll at frame 0
  double motion_px = 6;      // amplitude of the global sinusoidal motion
  double expression_px = 3;  // amplitude of the mouth and brow dots' own motion
  double blur_sigma = 0.8;
  double noise_sigma = 2.0;
  bool draw_tags = true;
  unsigned seed = 7;
  std::vector<Occluder> occluders;
};

struct Truth {
  cv::Point2d position;
  bool visible = true;  // false when an occluder (or the frame's edge) touches the marker
  bool hidden = false;  // true when an occluder covers all of it: nothing to see
  std::array<cv::Point2d, 4> corners{};  // tags
};

class SyntheticScene {
 public:
  SyntheticScene(const MarkerLayout& layout, SceneOptions options);
  // Frame k as 8-bit grey, and every layout marker's truth.
  cv::Mat render(int k, std::map<std::string, Truth>& truth) const;
  const SceneOptions& options() const { return options_; }

 private:
  const MarkerLayout& layout_;
  SceneOptions options_;
  cv::Mat texture_;  // larger than the frame, moved with the face
};

}  // namespace rostro::tracking::testing
