#pragma once
// Every camera rostro can open, V4L2 and libcamera, as text for `rostro devices`.

#include <string>
#include <vector>

#include "capture/libcamera_source.hpp"
#include "capture/v4l2_device.hpp"

namespace rostro::capture {

struct CameraList {
  std::vector<V4l2DeviceInfo> v4l2;
  std::vector<LibcameraCameraInfo> libcamera;
  bool libcamera_built = false;
  std::vector<std::string> problems;  // devices that could not be opened, and why

  bool empty() const { return v4l2.empty() && libcamera.empty(); }
};

// Scans /dev/video* and asks libcamera (when built in). Never throws for a device that
// cannot be opened: its reason goes into `problems`.
CameraList list_cameras();

// The list as readable text: one block per camera, its source spec and its modes (sizes
// grouped per pixel format, rates per size). With no camera, a line saying so.
std::string format_camera_list(const CameraList& list);

}  // namespace rostro::capture
