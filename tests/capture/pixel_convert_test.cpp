// YUYV and MJPEG into BGR, against pixels computed by hand from the BT.601 limited-range
// equations: R = 1.164 (Y-16) + 1.596 (V-128), G = 1.164 (Y-16) - 0.813 (V-128) - 0.391 (U-128),
// B = 1.164 (Y-16) + 2.018 (U-128).
#include "capture/pixel_convert.hpp"

#include <gtest/gtest.h>
#include <linux/videodev2.h>

#include <opencv2/imgcodecs.hpp>
#include <vector>

#include "facecore/error.hpp"

namespace rostro::capture {
namespace {

void expect_bgr(const cv::Mat& image, int x, int y, int b, int g, int r) {
  const auto px = image.at<cv::Vec3b>(y, x);
  EXPECT_NEAR(px[0], b, 1) << "blue at " << x << "," << y;
  EXPECT_NEAR(px[1], g, 1) << "green at " << x << "," << y;
  EXPECT_NEAR(px[2], r, 1) << "red at " << x << "," << y;
}

TEST(Fourcc, RoundTripsNames) {
  EXPECT_EQ(fourcc_from_string("YUYV"), V4L2_PIX_FMT_YUYV);
  EXPECT_EQ(fourcc_from_string("MJPG"), V4L2_PIX_FMT_MJPEG);
  EXPECT_EQ(fourcc_to_string(V4L2_PIX_FMT_YUYV), "YUYV");
  EXPECT_EQ(fourcc_to_string(V4L2_PIX_FMT_MJPEG), "MJPG");
  EXPECT_THROW(fourcc_from_string("MJPEG"), InputError);
}

TEST(YuyvToBgr, BlackWhiteAndGreyShareChroma) {
  // One row of 4 pixels: Y0 U Y1 V | Y2 U Y3 V.
  const std::vector<std::uint8_t> yuyv = {16, 128, 235, 128, 126, 128, 126, 128};
  const cv::Mat bgr = yuyv_to_bgr(yuyv.data(), yuyv.size(), 4, 1, 8);
  ASSERT_EQ(bgr.size(), cv::Size(4, 1));
  ASSERT_EQ(bgr.type(), CV_8UC3);
  expect_bgr(bgr, 0, 0, 0, 0, 0);        // Y=16: black
  expect_bgr(bgr, 1, 0, 255, 255, 255);  // Y=235: white
  expect_bgr(bgr, 2, 0, 128, 128, 128);  // 1.164 * 110 = 128.0
  expect_bgr(bgr, 3, 0, 128, 128, 128);
}

TEST(YuyvToBgr, SaturatedColours) {
  // BT.601 red (Y=81, U=90, V=240): R = 1.164*65 + 1.596*112 = 254.4,
  //   G = 75.7 - 91.1 + 14.9 = -0.5 -> 0, B = 75.7 - 76.7 = -1.0 -> 0.
  // A bluish pixel (Y=100, U=200, V=100): R = 97.8 - 44.7 = 53.1,
  //   G = 97.8 + 22.8 - 28.2 = 92.4, B = 97.8 + 145.3 = 243.1.
  const std::vector<std::uint8_t> yuyv = {81, 90, 81, 240, 100, 200, 100, 100};
  const cv::Mat bgr = yuyv_to_bgr(yuyv.data(), yuyv.size(), 4, 1, 8);
  ASSERT_FALSE(bgr.empty());
  expect_bgr(bgr, 0, 0, 0, 0, 254);
  expect_bgr(bgr, 1, 0, 0, 0, 254);
  expect_bgr(bgr, 2, 0, 243, 92, 53);
  expect_bgr(bgr, 3, 0, 243, 92, 53);
}

TEST(YuyvToBgr, HonoursDriverStride) {
  // 2x2 image with 4 padding bytes per row (bytesperline = 8); the padding must be skipped.
  const std::vector<std::uint8_t> yuyv = {16,  128, 16,  128, 9, 9, 9, 9,
                                          235, 128, 235, 128, 9, 9, 9, 9};
  const cv::Mat bgr = yuyv_to_bgr(yuyv.data(), yuyv.size(), 2, 2, 8);
  ASSERT_EQ(bgr.size(), cv::Size(2, 2));
  expect_bgr(bgr, 1, 0, 0, 0, 0);
  expect_bgr(bgr, 0, 1, 255, 255, 255);
}

TEST(YuyvToBgr, ShortBufferGivesEmptyImage) {
  const std::vector<std::uint8_t> yuyv(7, 128);
  EXPECT_TRUE(yuyv_to_bgr(yuyv.data(), yuyv.size(), 4, 1, 8).empty());
  EXPECT_TRUE(yuyv_to_bgr(yuyv.data(), yuyv.size(), 3, 1, 6).empty());  // odd width
}

TEST(DecodeMjpeg, DecodesAJpegAndRejectsGarbage) {
  cv::Mat image(48, 64, CV_8UC3, cv::Scalar(40, 120, 200));
  std::vector<std::uint8_t> jpeg;
  ASSERT_TRUE(cv::imencode(".jpg", image, jpeg, {cv::IMWRITE_JPEG_QUALITY, 95}));
  const cv::Mat decoded = decode_mjpeg(jpeg.data(), jpeg.size());
  ASSERT_EQ(decoded.size(), image.size());
  expect_bgr(decoded, 10, 10, 40, 120, 200);

  std::vector<std::uint8_t> garbage(500, 0x55);
  EXPECT_TRUE(decode_mjpeg(garbage.data(), garbage.size()).empty());
  garbage[0] = 0xff;
  garbage[1] = 0xd8;  // a JPEG start marker followed by nonsense
  EXPECT_TRUE(decode_mjpeg(garbage.data(), garbage.size()).empty());
}

}  // namespace
}  // namespace rostro::capture
