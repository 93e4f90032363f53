#pragma once
// The eye dots' rules (EyeOptions, part of TrackerOptions) and the eye's dots (MPEG-4 group 3)
// told apart: the inner corners, which those rules single out (rostro::tracking::internal); the
// lid midpoints are facecore's is_eyelid_midpoint.

#include "facecore/feature_point.hpp"

namespace rostro::tracking {

// The eye dots' rules (MPEG-4 group 3: the lids and the eye corners), TrackerOptions::eyes.
// What each does, measured on and off on the closed loop: docs/rules.md
// (scripts/rule-effects.sh).
struct EyeOptions {
  // The inner eye-corner dots (3.8, 3.11) sit where the eye slit's corner runs out in a thin
  // dark line. At 1280x720 the line joins the dot's blob at half its contrast and the blob
  // fails the roundness check; DotOptions::raise_share_for_roundness measures it higher up
  // instead (without it the inner corners are lost in most frames at 1280x720). They are not
  // edge-fitted: the edge fit's rays there run along the
  // line and the lashes (centre: inner_corners_symmetric_centre).
  bool inner_corners_raise_share = true;
  // The inner corners' centre where the blob best overlaps its own point reflection
  // (DotOptions::symmetric_centre) rather than the blob's centroid. The slit's corner, which
  // grows as the eye widens, pulls the centroid toward the eye, and the fit reads that as head
  // yaw; the symmetric centre stays on the dot.
  bool inner_corners_symmetric_centre = true;
  // The longest the inner eye-corner dots' blob may be (long over short axis) when the dots
  // are at least TrackerOptions::reference_dot_px wide; smaller dots keep
  // DotOptions::max_elongation (3). The inner corner sits in the hollow beside the nose, seen
  // steeply when the head turns: at 1280x720 and 16 degrees of yaw it is over 3 times as long
  // as wide, and rejected it was found again on the lash line. At 640x480 a blob that long is
  // the dot merged with the slit's corner line, hence the size condition.
  double inner_corner_max_elongation_large = 4;
  // Eye dots (lids, corners) found again after a loss: largest size over the larger of their
  // size when last seen and at the start (scaled as the face). A larger blob is the dot merged
  // with a dark neighbour (the pupil, the other lid's dot in a blink), whose centre is
  // neither's; it is not taken. A followed dot, and any dot off the eyes, keeps the looser 0.5-2x
  // of its start size: blur grows a followed eye dot as much as a merge does, and one dropped
  // for it was found again on a neighbour.
  double max_dot_growth_found = 1.2;
  // ... except that an eye dot last seen edge-on (at least edge_on_elongation long over short)
  // and lost for fewer frames than this is held to its size when last seen, not the larger of
  // that and its start size: an inner eye-corner dot seen edge-on under a head turn (a third of
  // its start width) merges with the eye slit's dark corner beside it into a blob about its
  // start size, whose centre lies pixels into the eye. Not after a round dot: one shrunk for a
  // while (half covered) comes back at its start size (the suite's occlusion clip loses it far
  // longer otherwise). 0: the start size always.
  int eye_size_memory_frames = 25;
  double edge_on_elongation = 2;
  // Lid dots: largest long / short axis of the blob. A lid dot merged with the pupil (the
  // upper lid lowered over it in a smile, the head pitched) keeps about a dot's area, so the
  // growth check above passes it, but is a tall blob, taller than a lone lid dot gets under
  // the closed loop's head turns (yaw +-25, pitch +-15).
  double max_lid_elongation = 1.8;

  // Throws InputError naming the first option out of range ("EyeOptions::...").
  void validate() const;
};

namespace internal {

// MPEG-4 group 3: the lids and the eye corners.
bool is_eye_point(const FeaturePointId& fp);
// MPEG-4 3.8, 3.11: the inner eye corners.
bool is_inner_eye_corner(const FeaturePointId& fp);

}  // namespace internal
}  // namespace rostro::tracking
