#pragma once
// Carrying a tracker's name corrections back to the frames it has already given out.
//
// The marker tracker names the dots on its first clear frame and looks again a few frames
// later (TrackerOptions::second_look_after); where the second look names a followed dot
// otherwise, the frames between were given out under the wrong name. The frame of the second
// look says which (TrackedFrame::corrections). A consumer that holds the frames can rename
// them: the dot followed as `from` is `to` back to where its track began (where it was lost,
// or jumped by half a spacing against its neighbours' motion: what it followed before is not
// known), and `from` is left unseen over those frames unless another correction names a dot
// it. A take held whole applies each frame's
// corrections to the frames before it; one written as it goes holds its last frames in a
// CorrectionWindow.

#include <span>
#include <string>
#include <vector>

#include "tracking/tracked_frame.hpp"

namespace rostro::tracking {

// Applies `now`'s corrections to the `earlier` frames (in frame order) from
// now.corrected_since on. Nothing when `now` has none.
void apply_name_corrections(std::span<TrackedFrame> earlier, const TrackedFrame& now);

// The corrections of `frame` in words: "frames 0-9: lip_bot was lip_bot_l, mouth_l no marker".
std::string describe_corrections(const TrackedFrame& frame);

// Appends the tracker's newest frame to a take held whole, first correcting the frames before
// it by it.
void append_corrected(std::vector<TrackedFrame>& take, TrackedFrame frame);

// Holds the last frames of a take written as it goes until no later frame can correct them.
class CorrectionWindow {
 public:
  // `horizon`: FaceTracker::correction_horizon() (0: frames pass straight through).
  explicit CorrectionWindow(long horizon) : horizon_(horizon) {}
  // Takes the tracker's newest frame, corrects the held ones by it, and hands back the frames
  // no later frame can correct, oldest first.
  std::vector<TrackedFrame> push(TrackedFrame frame);
  // The frames still held, oldest first (at the end of the take, or when it stops).
  std::vector<TrackedFrame> flush();
  // The frames still held, oldest first, for rewriting (StartBackfill).
  std::span<TrackedFrame> held() { return held_; }

 private:
  long horizon_;
  std::vector<TrackedFrame> held_;  // a horizon's frames: moved along, not reallocated
};

}  // namespace rostro::tracking
