#pragma once
// What every tracker of a face gives the stages after it: one TrackedFrame per image, every
// marker of its layout in layout order. MarkerTracker follows worn dots and AprilTags;
// LandmarkTracker finds the 68 iBUG landmarks of a bare face. Calibration, the fit and
// everything after them see only this.

#include <memory>
#include <opencv2/core.hpp>

#include "tracking/layout.hpp"
#include "tracking/tracked_frame.hpp"

namespace rostro::tracking {

class FaceTracker {
 public:
  virtual ~FaceTracker() = default;
  // `image`: 8-bit grey or BGR. Every layout marker appears in the result, in layout order;
  // what could not be measured on this frame is there with valid = false.
  virtual TrackedFrame track(const cv::Mat& image, long frame, double time_s) = 0;
  // Whether the face has been found (markers identified, or a face detected) at least once.
  virtual bool started() const = 0;
  virtual const MarkerLayout& layout() const = 0;
  // How many frames back a frame's name corrections (TrackedFrame::corrections) reach as a
  // rule: a consumer that holds this many frames before writing them can correct them (a
  // marker tracker's pair given back may reach further; a take held whole corrects all).
  // 0: none.
  virtual long correction_horizon() const { return 0; }
  // A tracker like this one started from `start`'s positions, for following them back over
  // the frames before it (tracking/start_backfill.hpp); none where that is not done.
  virtual std::unique_ptr<FaceTracker> started_from(const TrackedFrame& start) const {
    (void)start;
    return nullptr;
  }
  // Draws the last frame's state (markers or landmarks, valid or not) onto `image`.
  virtual void draw(cv::Mat& image, long frame) const = 0;
};

}  // namespace rostro::tracking
