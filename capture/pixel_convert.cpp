#include "capture/pixel_convert.hpp"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "facecore/error.hpp"

namespace rostro::capture {

std::uint32_t fourcc_from_string(const std::string& name) {
  if (name.size() != 4) {
    throw InputError("pixel format '" + name +
                     "': expected a four-letter code such as MJPG or YUYV");
  }
  return static_cast<std::uint32_t>(static_cast<unsigned char>(name[0])) |
         static_cast<std::uint32_t>(static_cast<unsigned char>(name[1])) << 8 |
         static_cast<std::uint32_t>(static_cast<unsigned char>(name[2])) << 16 |
         static_cast<std::uint32_t>(static_cast<unsigned char>(name[3])) << 24;
}

std::string fourcc_to_string(std::uint32_t fourcc) {
  std::string name(4, '?');
  for (int i = 0; i < 4; ++i) {
    const auto c = static_cast<char>((fourcc >> (8 * i)) & 0xffU);
    if (c >= 32 && c < 127) name[static_cast<std::size_t>(i)] = c;
  }
  return name;
}

cv::Mat yuyv_to_bgr(const std::uint8_t* data, std::size_t size, int width, int height,
                    std::size_t bytes_per_line) {
  if (data == nullptr || width <= 0 || height <= 0 || width % 2 != 0) return {};
  const auto row_bytes = static_cast<std::size_t>(width) * 2;
  if (bytes_per_line < row_bytes) bytes_per_line = row_bytes;
  const auto needed = bytes_per_line * static_cast<std::size_t>(height - 1) + row_bytes;
  if (size < needed) return {};
  // A header over the driver's buffer (no copy); cvtColor writes a new image, so the result
  // stays valid after the buffer goes back to the driver.
  const cv::Mat packed(height, width, CV_8UC2, const_cast<std::uint8_t*>(data), bytes_per_line);
  cv::Mat bgr;
  cv::cvtColor(packed, bgr, cv::COLOR_YUV2BGR_YUYV);
  return bgr;
}

cv::Mat decode_mjpeg(const std::uint8_t* data, std::size_t size) {
  if (data == nullptr || size < 4) return {};
  // A JPEG starts with SOI (FF D8); anything else is a torn or empty buffer.
  if (data[0] != 0xff || data[1] != 0xd8) return {};
  const cv::Mat encoded(1, static_cast<int>(size), CV_8UC1, const_cast<std::uint8_t*>(data));
  try {
    return cv::imdecode(encoded, cv::IMREAD_COLOR);
  } catch (const cv::Exception&) {
    return {};
  }
}

}  // namespace rostro::capture
