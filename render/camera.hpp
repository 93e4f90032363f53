#pragma once
// Where the camera stands: an orbit around the head's centre (yaw, pitch, roll), a field of
// view, and a distance that by default is chosen so the head's bounding box fills the view.

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <string>
#include <string_view>

#include "render/render_mesh.hpp"

namespace rostro::render {

struct CameraPose {
  double yaw_deg = 0.0;    // positive moves the camera toward the face's left (+x)
  double pitch_deg = 0.0;  // positive raises the camera, looking down on the face
  double roll_deg = 0.0;   // positive turns the image counter-clockwise
  double fov_deg = 25.0;   // vertical field of view
  double distance = 0.0;   // from the framing centre, model units; 0 frames automatically
  double margin = 1.15;    // automatic framing: the box spans 1/margin of the view

  static CameraPose front();
  static CameraPose three_quarter();
};

// "front", "three-quarter" (or "3/4"), or "yaw,pitch,roll[,distance[,fov]]" in degrees and
// model units. Throws rostro::InputError naming the text and the expected forms.
CameraPose parse_camera(std::string_view text);
std::string describe(const CameraPose& pose);

struct CameraMatrices {
  Eigen::Matrix4f view = Eigen::Matrix4f::Identity();
  Eigen::Matrix4f projection = Eigen::Matrix4f::Identity();
  Eigen::Vector3f eye = Eigen::Vector3f::Zero();
  double distance = 0.0;  // the distance actually used
};

// Places the camera for a viewport of `aspect` = width / height around `frame` (usually the
// neutral mesh's bounds, so the camera stays put while the face moves).
CameraMatrices frame_camera(const CameraPose& pose, const Bounds& frame, double aspect);

// Model points to the pixels of a width x height image seen through `m`, with OpenCV's
// convention (pixel centres at integers, row 0 on top): where the renderer draws them.
struct PixelProjector {
  CameraMatrices m;
  int width = 0, height = 0;
  // False behind the camera.
  bool project(const Eigen::Vector3f& p, cv::Point2d& out) const;
};

}  // namespace rostro::render
