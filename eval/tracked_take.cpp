#include "eval/tracked_take.hpp"

#include <utility>

#include "tracking/name_corrections.hpp"

namespace rostro::eval {

TrackedTake::TrackedTake(tracking::MarkerTracker& tracker, double fps)
    : tracker_(tracker), fps_(fps), backfill_(tracker, tracker.correction_horizon()) {}

void TrackedTake::add(const cv::Mat& image) {
  const auto n = static_cast<long>(frames_.size());
  tracking::TrackedFrame now = tracker_.track(image, n, static_cast<double>(n) / fps_);
  // Counted lost as unidentified as they came: the tables say what was written.
  lost_by_[static_cast<std::size_t>(tracking::LostReason::Unidentified)] -=
      backfill_.take(now, frames_, image);
  tracking::append_corrected(frames_, std::move(now));
  for (const tracking::MarkerState& s : tracker_.states())
    if (!s.valid || s.held) ++lost_by_[static_cast<std::size_t>(s.lost_reason)];
}

}  // namespace rostro::eval
