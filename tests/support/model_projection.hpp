#pragma once
// For the mapping tests that render frames from a fit's own marker model, so that the fit's
// only unknowns are the FAPs and pose it solves for.

#include <map>
#include <opencv2/calib3d.hpp>

#include "calib/camera_intrinsics.hpp"
#include "mapping/marker_model.hpp"
#include "tracking/tracked_frame.hpp"

namespace rostro::test {

// Where `marker` appears through `camera` with the head at `pose` and `faps` (FAP id ->
// value) moving it along its model steps.
inline cv::Point2d project_model_marker(const mapping::ModelMarker& marker,
                                        const std::map<int, double>& faps,
                                        const tracking::HeadPose& pose,
                                        const calib::CameraIntrinsics& camera) {
  Eigen::Vector3d x = marker.neutral;
  for (const mapping::FapStep& s : marker.faps)
    if (auto v = faps.find(s.fap); v != faps.end()) x += v->second * s.step;
  cv::Matx33d R;
  cv::Rodrigues(pose.rotation, R);
  const cv::Vec3d c = R * cv::Vec3d(x.x(), x.y(), x.z()) + pose.translation;
  return {camera.fx * c[0] / c[2] + camera.cx, camera.fy * c[1] / c[2] + camera.cy};
}

}  // namespace rostro::test
