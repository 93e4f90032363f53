#pragma once
// Cameras through libcamera (Raspberry Pi and other ISP-based cameras; USB webcams appear
// here too through libcamera's UVC handler). Compiled in when CMake finds libcamera;
// otherwise these functions report that rostro was built without it.

#include <memory>
#include <string>
#include <vector>

#include "capture/frame_source.hpp"
#include "capture/open_source.hpp"

namespace rostro::capture {

struct LibcameraMode {
  std::string pixel_format;  // libcamera's name: "YUYV", "MJPEG", "RGB888", ...
  int width = 0;
  int height = 0;
};

struct LibcameraCameraInfo {
  std::string id;        // libcamera's camera id (stable across runs)
  std::string model;     // properties::Model, when the pipeline knows it
  std::string location;  // front, back, external
  std::vector<LibcameraMode> modes;
  double min_fps = 0, max_fps = 0;  // from FrameDurationLimits; 0 when unknown
};

// Whether this build of rostro includes the libcamera source.
bool libcamera_built();

// The cameras libcamera sees, in its order (the index in "libcamera:<index>").
// Empty when there are none or rostro was built without libcamera.
std::vector<LibcameraCameraInfo> list_libcamera_cameras();

// `id_or_index` is a camera id or an index into list_libcamera_cameras(). Throws
// InputError when the camera is missing, busy, refuses the configuration, or rostro was
// built without libcamera. Exposure for libcamera is given in the same 100 us units as
// V4L2 (converted to microseconds); gain is the analogue gain factor.
std::unique_ptr<FrameSource> open_libcamera_source(const std::string& id_or_index,
                                                   const SourceOptions& options);

}  // namespace rostro::capture
