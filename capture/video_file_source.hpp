#pragma once
// A recorded video read through OpenCV's FFmpeg backend. Timestamps come from the
// container (presentation times), the sequence number is the frame index.

#include <memory>
#include <string>

#include "capture/frame_source.hpp"

namespace rostro::capture {

// Throws InputError naming the file when it is missing or FFmpeg cannot open it.
std::unique_ptr<FrameSource> open_video_file_source(const std::string& path);

}  // namespace rostro::capture
