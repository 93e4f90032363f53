#pragma once
// One entry point that turns a source spec into a FrameSource:
//   "/dev/videoN" (or any /dev/ path, e.g. /dev/v4l/by-id/...) -> V4L2 device (direct ioctl, mmap
//   streaming) "libcamera:<id or index>"    -> libcamera camera (when rostro was built with
//   libcamera) an existing directory        -> image folder, files sorted by name anything else ->
//   video file (OpenCV / FFmpeg)
// Every failure to open (missing file, busy or absent device, unreadable image) throws
// rostro::InputError with one line naming the spec.

#include <memory>
#include <optional>
#include <string>

#include "capture/frame_source.hpp"

namespace rostro::capture {

struct SourceOptions {
  double fps = 0;                  // 0 = the device's or file's default (image folders: 25)
  int width = 0, height = 0;       // 0 = the device's default / largest sensible mode
  std::string pixel_format;        // FourCC such as "MJPG" or "YUYV"; empty = let rostro choose
  std::optional<double> exposure;  // fixed exposure (V4L2 units: 100 us); unset = auto
  std::optional<double> gain;      // fixed gain (driver units); unset = driver default
};

std::unique_ptr<FrameSource> open_frame_source(const std::string& spec,
                                               const SourceOptions& options = {});

}  // namespace rostro::capture
