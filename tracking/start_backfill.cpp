#include "tracking/start_backfill.hpp"

#include <algorithm>
#include <set>
#include <string>
#include <utility>

namespace rostro::tracking {

StartBackfill::StartBackfill(const FaceTracker& tracker, long max_frames)
    : tracker_(tracker), max_frames_(max_frames) {}

long StartBackfill::take(TrackedFrame& frame, std::span<TrackedFrame> before,
                         const cv::Mat& image) {
  if (!frame.corrections.empty() && frame.corrected_since == started_at_ &&
      filled_from_ < started_at_)
    frame.corrected_since = filled_from_;
  const bool was_started = std::exchange(was_started_, tracker_.started());
  if (!was_started_) {
    hold(image);
    return 0;
  }
  return was_started ? 0 : fill(before, frame, image);
}

void StartBackfill::hold(const cv::Mat& image) {
  if (max_frames_ <= 0) return;
  held_.push_back(image.clone());
  while (static_cast<long>(held_.size()) > max_frames_) held_.pop_front();
}

long StartBackfill::fill(std::span<TrackedFrame> before, const TrackedFrame& start,
                         const cv::Mat& start_image) {
  started_at_ = start.frame, filled_from_ = start.frame;
  long filled = 0;
  const std::unique_ptr<FaceTracker> back =
      held_.empty() || before.empty() ? nullptr : tracker_.started_from(start);
  if (!back) {
    held_.clear();
    return filled;
  }
  std::set<std::string> followed;
  for (const MarkerObservation& o : back->track(start_image, 0, 0).markers)
    if (o.valid) followed.insert(o.marker);
  const MarkerLayout& layout = tracker_.layout();
  const size_t n = std::min(before.size(), held_.size());
  for (size_t k = 1; k <= n && back->started(); ++k) {
    const TrackedFrame step =
        back->track(held_[held_.size() - k], static_cast<long>(k), static_cast<double>(k));
    // A tag lost is covered or blurred past reading, and no other marker's place is taken.
    for (const MarkerObservation& o : step.markers)
      if (!o.valid && layout.find(o.marker) && layout.find(o.marker)->is_tag())
        followed.erase(o.marker);
    const bool all_followed = std::all_of(
        step.markers.begin(), step.markers.end(),
        [&](const MarkerObservation& o) { return o.valid || !followed.count(o.marker); });
    if (!all_followed) break;
    TrackedFrame& f = before[before.size() - k];
    for (const MarkerObservation& o : step.markers)
      if (followed.count(o.marker))
        for (MarkerObservation& mine : f.markers)
          if (mine.marker == o.marker && !mine.valid) {
            mine.position = o.position, mine.valid = true, mine.quality = o.quality;
            ++filled;
          }
    filled_from_ = f.frame;
  }
  held_.clear();
  return filled;
}

}  // namespace rostro::tracking
