#include "capture/open_source.hpp"

#include <filesystem>

#include "capture/image_folder_source.hpp"
#include "capture/libcamera_source.hpp"
#include "capture/v4l2_source.hpp"
#include "capture/video_file_source.hpp"
#include "facecore/error.hpp"

namespace rostro::capture {

std::unique_ptr<FrameSource> open_frame_source(const std::string& spec,
                                               const SourceOptions& options) {
  if (spec.empty())
    throw InputError(
        "empty source: expected a video file, an image folder, /dev/videoN or libcamera:N");
  // Anything under /dev is a device: /dev/videoN, or a stable /dev/v4l/by-id/... link.
  if (spec.rfind("/dev/", 0) == 0) return open_v4l2_source(spec, options);
  constexpr std::string_view kLibcamera = "libcamera:";
  if (spec.rfind(kLibcamera, 0) == 0)
    return open_libcamera_source(spec.substr(kLibcamera.size()), options);
  std::error_code ec;
  if (std::filesystem::is_directory(spec, ec)) return open_image_folder_source(spec, options.fps);
  return open_video_file_source(spec);
}

}  // namespace rostro::capture
