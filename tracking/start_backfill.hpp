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

  // Takes each frame the tracker gives out, before the consumer adds it to `before`, the frames
  // it still holds in frame order: extends the frame's corrections to the filled frames when
  // they reach back to the start (a second look), keeps its image while the tracker has not
  // started (the last max_frames), and on the frame the tracker starts on follows its markers
  // back over the held images into `before` (the last of them the frame just before it).
  // Returns the observations made valid (0 on every frame but a start).
  long take(TrackedFrame& frame, std::span<TrackedFrame> before, const cv::Mat& image);
  // The first frame the last start filled (its own frame: none), -1 before any start.
  long filled_from() const { return filled_from_; }
  long started_at() const { return started_at_; }

 private:
  const FaceTracker& tracker_;
  long max_frames_;
  std::deque<cv::Mat> held_;
  bool was_started_ = false;
  long started_at_ = -1, filled_from_ = -1;

  void hold(const cv::Mat& image);
  long fill(std::span<TrackedFrame> before, const TrackedFrame& start, const cv::Mat& start_image);
};

}  // namespace rostro::tracking
