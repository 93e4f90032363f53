#pragma once
// Capture modes (pixel format, size, frame rate) and the choice of one for a request.
// The choice is a pure function so it can be tested without a camera.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace rostro::capture {

// One mode a device offers. The frame interval is kept as the driver's fraction
// (seconds per frame = interval_num / interval_den) so it can be set back exactly.
struct CaptureMode {
  std::uint32_t fourcc = 0;
  int width = 0;
  int height = 0;
  std::uint32_t interval_num = 1;
  std::uint32_t interval_den = 30;

  double fps() const {
    return interval_num == 0 ? 0.0 : static_cast<double>(interval_den) / interval_num;
  }
  friend bool operator==(const CaptureMode&, const CaptureMode&) = default;
};

// What the user asked for; zero / empty means "no preference".
struct ModeRequest {
  int width = 0;
  int height = 0;
  double fps = 0;
  std::string pixel_format;  // "MJPG", "YUYV", ...
};

// Pixel formats rostro can turn into BGR: YUYV and MJPEG (MJPG; JPEG is accepted as MJPEG).
bool is_decodable_format(std::uint32_t fourcc);

// The mode to use for `request`, or nullopt when no decodable mode satisfies it.
// Rules, in order:
//   - only decodable formats; the requested pixel format, size (width and/or height) and
//     frame rate (within 1%) must match exactly when given;
//   - prefer modes that reach the requested rate, or 25 fps when none was requested;
//   - without a requested size: the largest size up to 1920x1080 (tracking wants pixels,
//     but decoding 4K MJPEG every frame would cost more than it gains), else the smallest
//     larger one;
//   - then the highest frame rate (or the one closest to the requested rate);
//   - then YUYV before MJPEG (no compression artefacts around the markers).
std::optional<CaptureMode> choose_mode(const std::vector<CaptureMode>& modes,
                                       const ModeRequest& request);

// "MJPG 1280x720 @ 30 fps"
std::string describe_mode(const CaptureMode& mode);
// "1280x720 @ 30 fps MJPG" style summary of the request, "any mode" when empty.
std::string describe_request(const ModeRequest& request);

}  // namespace rostro::capture
