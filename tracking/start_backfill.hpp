#pragma once
// The frames before a take's start, filled by tracking backwards from it.
//
// The marker tracker starts on its first confident naming; the frames before it (a blurred
// first frame, a face entering, dots too big to name at once) are given out with every marker
// invalid. A consumer that still holds them can fill them: a second tracker starts from the
// start frame's positions and follows the markers back over the held images, newest first, and
// the filling stops on the first frame where it loses any of the dots (a tag lost is only left
// out: covered or blurred past reading, it takes no other marker's place). A face moving faster
// than LK follows (a late start's face entering at 40-50 px a frame) slides some dots onto their
// neighbours, all alike, which no check between the dots catches, and loses others; a blurred
// or covered frame loses some. A lost dot is not looked for again going back: what it would be
// found on has no naming behind it.

#include <deque>
#include <opencv2/core.hpp>
#include <span>

#include "tracking/face_tracker.hpp"
#include "tracking/tracked_frame.hpp"

namespace rostro::tracking {

class StartBackfill {
 public:
  // `tracker`: the take's own (FaceTracker::started_from gives the back tracker; a tracker that
  // gives none fills nothing). `max_frames`: the most images held, the frames a consumer can
  // still rewrite.
  StartBackfill(const FaceTracker& tracker, long max_frames);

  // Keeps the image of a frame the tracker has not started on (its last max_frames).
  void hold(const cv::Mat& image);
  // On the frame the tracker started on: follows the markers of `start` back over the held
  // images and writes them into `before`, the frames just before `start` in frame order (the
  // last of them the frame before it). Returns the first frame filled (start.frame: none).
  // The held images are released.
  long fill(std::span<TrackedFrame> before, const TrackedFrame& start, const cv::Mat& start_image);
  // A later frame whose corrections reach back to the start (a second look): they reach the
  // filled frames too.
  void extend_corrections(TrackedFrame& frame) const;
  // The observations the last fill() made valid.
  long filled_observations() const { return filled_observations_; }

 private:
  const FaceTracker& tracker_;
  long max_frames_;
  std::deque<cv::Mat> held_;
  long started_at_ = -1, filled_from_ = -1, filled_observations_ = 0;
};

}  // namespace rostro::tracking
