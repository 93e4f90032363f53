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

struct TrackedFrame {
  long frame = 0;
  double time_s = 0;
  std::vector<MarkerObservation> markers;
  std::optional<HeadPose> head_pose;
  // On the frame where the markers were identified, or their identities corrected: how and
  // how surely, in words (tracking/identify.hpp's describe()); empty elsewhere.
  std::string identification;
};

}  // namespace rostro::tracking
