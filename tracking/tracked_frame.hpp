#pragma once
// What tracking produces per frame: every marker of the layout with its image position and
// whether it could be trusted, plus the head pose when rigid markers give one.

#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "facecore/feature_point.hpp"

namespace rostro::tracking {

struct MarkerObservation {
  std::string marker;  // the layout's id: "brow_l_in" or "tag36h11:3"
  FeaturePointId feature_point;
  cv::Point2d position;  // pixels; meaningless when !valid
  bool valid = false;    // false when occluded, lost or failing the checks
  double quality = 0;    // 0..1, the tracker's confidence
};

struct HeadPose {
  cv::Vec3d rotation;     // Rodrigues vector, camera frame
  cv::Vec3d translation;  // millimetres, camera frame
};

// A name the tracker followed on the wrong dot: the dot it called `from` was `to` (empty: no
// marker at all, a name followed on a blob that is none).
struct NameCorrection {
  std::string from, to;
  // The first frame it holds for, where that is later than the frame's corrected_since (-1:
  // from corrected_since on).
  long since = -1;
  bool operator==(const NameCorrection&) const = default;
};

struct TrackedFrame {
  long frame = 0;
  double time_s = 0;
  std::vector<MarkerObservation> markers;
  std::optional<HeadPose> head_pose;
  // On the frame where the markers were identified, or their identities corrected: how and
  // how surely, in words (tracking/identify.hpp's describe()); empty elsewhere.
  std::string identification;
  // On a frame where the tracker found names it had followed since frame `corrected_since`
  // wrong (FaceTracker::correction_horizon()): what each was. This frame is named rightly
  // already; the earlier ones take the corrections (tracking/name_corrections.hpp).
  long corrected_since = -1;
  std::vector<NameCorrection> corrections;
};

}  // namespace rostro::tracking
