#pragma once
// A take tracked frame by frame as an evaluation renders it, written as `rostro track` writes
// it: the frames before the start followed back from it (tracking/start_backfill.hpp), the name
// corrections applied (tracking/name_corrections.hpp), and every marker-frame reported lost
// counted by the rule that dropped it.

#include <array>
#include <opencv2/core.hpp>
#include <vector>

#include "tracking/marker_tracker.hpp"
#include "tracking/start_backfill.hpp"
#include "tracking/tracked_frame.hpp"

namespace rostro::eval {

class TrackedTake {
 public:
  // `fps`: the take's frame rate, for each frame's time.
  TrackedTake(tracking::MarkerTracker& tracker, double fps);

  // Tracks the next frame (8-bit BGR or grey).
  void add(const cv::Mat& image);

  const std::vector<tracking::TrackedFrame>& frames() const { return frames_; }
  std::vector<tracking::TrackedFrame> take_frames() { return std::move(frames_); }
  // Marker-frames lost, by tracking::LostReason, as written: every layout marker, visible in
  // the truth or not (a frame filled back from the start no longer counts as unidentified).
  const std::array<long, tracking::kLostReasonCount>& lost_by() const { return lost_by_; }

 private:
  tracking::MarkerTracker& tracker_;
  double fps_;
  tracking::StartBackfill backfill_;  // as far back as `rostro track` holds frames
  std::vector<tracking::TrackedFrame> frames_;
  std::array<long, tracking::kLostReasonCount> lost_by_{};
};

}  // namespace rostro::eval
