#pragma once
// Steadies a landmark regressor's points with optical flow. A cascade of regression trees
// (dlib's shape predictor) fits each frame anew from pixel differences that sensor noise
// flips, so on a still face its points wander by a pixel or more from frame to frame. Each
// point is instead carried from the last frame by pyramidal Lucas-Kanade (which moves a still
// point by hundredths of a pixel and a moving one with no lag) and pulled toward the new fit:
//   out = flow + w (fit - flow),  w = follow_share + (1 - follow_share) min(1, d / full_trust)^2
// where d is the distance between fit and flow in eye distances. Where they agree the fit
// only corrects the flow's drift, a follow_share a frame; where they part (flow lost on
// smooth skin, a blink the flow cannot follow) the fit takes over within a frame.

#include <opencv2/core.hpp>
#include <vector>

namespace rostro::tracking {

struct StabiliserOptions {
  double follow_share = 0.15;  // the fit's weight where it agrees with the flow
  double full_trust = 0.06;    // fit-to-flow distance (eye distances) where the fit wins
  int lk_window = 15;          // pixels
  int lk_levels = 2;           // pyramid levels above the image
  void validate() const;       // throws InputError naming the option
};

class LandmarkStabiliser {
 public:
  explicit LandmarkStabiliser(StabiliserOptions options = {});
  // Carries the last blended points into the 8-bit grey `gray` by the flow (the face's
  // motion: one similarity through the flow of every point), `eyes` the eye distance in
  // pixels. Returns the share of points that moved with the face (found by the flow and within
  // 0.02 eye distances of that motion): near 1 while the face is in view, low when it is
  // covered or gone, 0 with nothing to carry (the first frame, after reset()).
  double predict(const cv::Mat& gray, double eyes);
  // This frame's fitted points pulled from the prediction toward `fit` (see above); `fit`
  // itself when predict() carried nothing. Keeps `gray` and the result for the next frame.
  std::vector<cv::Point2d> blend(const cv::Mat& gray, const std::vector<cv::Point2d>& fit,
                                 double eyes);
  void reset() { previous_.clear(), predicted_.clear(); }

 private:
  StabiliserOptions options_;
  cv::Mat previous_gray_;
  std::vector<cv::Point2d> previous_, predicted_;
};

}  // namespace rostro::tracking
