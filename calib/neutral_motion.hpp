#pragma once
// How much a face moves over frames meant to show it neutral and still. A calibration takes
// the median of those frames as the actor's neutral face, so a jaw that opens or a smile in
// them becomes part of "neutral" and reads as 0 for the rest of the take, without a word.
//
// Each frame's markers are aligned to their median shape by a 2D affine map, which removes
// the head's sway, roll and small turns to first order (a weak-perspective view of a flat
// face); what remains is the face's own motion, and the parallax of a head turning further
// than a calibration should see.

#include <optional>
#include <string>
#include <vector>

#include "tracking/tracked_frame.hpp"

namespace rostro::calib {

struct NeutralMotion {
  std::string marker;          // the marker that moves most
  double displacement_px = 0;  // its 90th-percentile distance from its median, aligned
  double face_size_px = 0;     // RMS distance of the median markers from their centroid
  double share() const { return face_size_px > 0 ? displacement_px / face_size_px : 0; }
};

// Nullopt when fewer than two frames have four or more of the median shape's markers.
std::optional<NeutralMotion> measure_neutral_motion(
    const std::vector<tracking::TrackedFrame>& frames);

// A face moving more than this share of its size is not still. On rostro's synthetic clips
// a still neutral second moves its worst marker by 0.1-1.3 % (noise, blur and low light, a
// bare face's landmarks), the first second of the range-of-motion drive, where the jaw
// starts to open, by 3.4-3.7 % (docs/mapping.md, "A still neutral").
inline constexpr double kMaxNeutralMotionShare = 0.025;

// One line for the user when `motion` exceeds kMaxNeutralMotionShare; empty otherwise.
std::string neutral_motion_warning(const std::optional<NeutralMotion>& motion);

}  // namespace rostro::calib
