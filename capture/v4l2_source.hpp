#pragma once
// A V4L2 camera read directly through ioctls with mmap streaming: the mode is negotiated
// with choose_mode, exposure and gain can be fixed, and every frame carries the driver's
// timestamp and sequence number so dropped frames are counted.

#include <memory>
#include <string>

#include "capture/frame_source.hpp"
#include "capture/open_source.hpp"

namespace rostro::capture {

// Opens and starts streaming. Throws InputError naming the device when it is missing,
// busy, not a capture device, offers no mode matching `options`, or refuses a fixed
// exposure or gain that was asked for.
std::unique_ptr<FrameSource> open_v4l2_source(const std::string& path,
                                              const SourceOptions& options);

}  // namespace rostro::capture
