#pragma once
// Pixel conversions for camera buffers: packed YUYV (YUV 4:2:2) and MJPEG into BGR, and
// FourCC codes to and from their four-letter names.

#include <cstddef>
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>

namespace rostro::capture {

// The FourCC code of a four-letter name ("YUYV" -> V4L2_PIX_FMT_YUYV). Throws InputError
// when the name is not exactly four characters.
std::uint32_t fourcc_from_string(const std::string& name);
// "YUYV" for V4L2_PIX_FMT_YUYV; unprintable bytes become '?'.
std::string fourcc_to_string(std::uint32_t fourcc);

// Packed YUYV (Y0 U Y1 V per two pixels, BT.601 limited range as webcams send it) into a
// new BGR image. `bytes_per_line` is the driver's stride (>= 2 * width); `size` is the
// number of bytes available, checked so a short buffer never reads out of bounds.
// Returns an empty Mat when the buffer is too short for the image.
cv::Mat yuyv_to_bgr(const std::uint8_t* data, std::size_t size, int width, int height,
                    std::size_t bytes_per_line);

// One MJPEG frame (a JPEG image, possibly without Huffman tables as many webcams send it)
// into a new BGR image. Returns an empty Mat when the data does not decode.
cv::Mat decode_mjpeg(const std::uint8_t* data, std::size_t size);

}  // namespace rostro::capture
