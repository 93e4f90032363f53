// choose_mode: the mode picked for a request from a device's list.
#include "capture/capture_mode.hpp"

#include <gtest/gtest.h>
#include <linux/videodev2.h>

namespace rostro::capture {
namespace {

constexpr std::uint32_t kYuyv = V4L2_PIX_FMT_YUYV;
constexpr std::uint32_t kMjpg = V4L2_PIX_FMT_MJPEG;
constexpr std::uint32_t kH264 = V4L2_PIX_FMT_H264;

CaptureMode mode(std::uint32_t fourcc, int w, int h, std::uint32_t fps) {
  return {fourcc, w, h, 1, fps};
}

// A typical UVC webcam: YUYV is slow at large sizes, MJPEG is fast everywhere.
std::vector<CaptureMode> webcam() {
  return {mode(kYuyv, 640, 480, 30),  mode(kYuyv, 640, 480, 15),   mode(kYuyv, 1280, 720, 10),
          mode(kYuyv, 1920, 1080, 5), mode(kMjpg, 640, 480, 30),   mode(kMjpg, 1280, 720, 60),
          mode(kMjpg, 1280, 720, 30), mode(kMjpg, 1920, 1080, 30), mode(kMjpg, 3840, 2160, 30),
          mode(kH264, 1920, 1080, 30)};
}

TEST(ChooseMode, DefaultIsLargestFastModeUpTo1080p) {
  const auto chosen = choose_mode(webcam(), {});
  ASSERT_TRUE(chosen);
  EXPECT_EQ(*chosen, mode(kMjpg, 1920, 1080, 30));
}

TEST(ChooseMode, RequestedSizePicksHighestRateThere) {
  const auto chosen = choose_mode(webcam(), {1280, 720, 0, ""});
  ASSERT_TRUE(chosen);
  EXPECT_EQ(*chosen, mode(kMjpg, 1280, 720, 60));
}

TEST(ChooseMode, RequestedRateIsMatched) {
  const auto chosen = choose_mode(webcam(), {1280, 720, 30, ""});
  ASSERT_TRUE(chosen);
  EXPECT_EQ(*chosen, mode(kMjpg, 1280, 720, 30));
  // 29.97 is within 1% of 30
  const auto ntsc = choose_mode(webcam(), {1280, 720, 29.97, ""});
  ASSERT_TRUE(ntsc);
  EXPECT_EQ(ntsc->fps(), 30.0);
}

TEST(ChooseMode, PrefersYuyvWhenItIsAsFast) {
  const auto chosen = choose_mode(webcam(), {640, 480, 0, ""});
  ASSERT_TRUE(chosen);
  EXPECT_EQ(*chosen, mode(kYuyv, 640, 480, 30));
}

TEST(ChooseMode, RequestedPixelFormatIsHonoured) {
  const auto chosen = choose_mode(webcam(), {0, 0, 0, "YUYV"});
  ASSERT_TRUE(chosen);
  // No YUYV mode reaches 25 fps except 640x480, which beats the larger slow ones.
  EXPECT_EQ(*chosen, mode(kYuyv, 640, 480, 30));
  const auto slow = choose_mode(webcam(), {1920, 1080, 0, "YUYV"});
  ASSERT_TRUE(slow);
  EXPECT_EQ(*slow, mode(kYuyv, 1920, 1080, 5));
}

TEST(ChooseMode, NoMatchGivesNothing) {
  EXPECT_FALSE(choose_mode(webcam(), {1024, 768, 0, ""}));       // size not offered
  EXPECT_FALSE(choose_mode(webcam(), {1920, 1080, 60, ""}));     // rate not offered there
  EXPECT_FALSE(choose_mode(webcam(), {0, 0, 0, "H264"}));        // offered but not decodable
  EXPECT_FALSE(choose_mode(webcam(), {0, 0, 0, "NV12"}));        // not offered
  EXPECT_FALSE(choose_mode({}, {}));                             // empty list
  EXPECT_FALSE(choose_mode({mode(kH264, 1920, 1080, 30)}, {}));  // nothing decodable
}

TEST(ChooseMode, OnlyLargeModesPicksTheSmallestAboveTheCap) {
  const std::vector<CaptureMode> modes = {mode(kMjpg, 3840, 2160, 30), mode(kMjpg, 2560, 1440, 30)};
  const auto chosen = choose_mode(modes, {});
  ASSERT_TRUE(chosen);
  EXPECT_EQ(*chosen, mode(kMjpg, 2560, 1440, 30));
}

TEST(ChooseMode, SlowModesUsedWhenNothingIsFast) {
  // Nothing reaches 25 fps: the size rule decides, then the rate.
  const std::vector<CaptureMode> modes = {mode(kYuyv, 640, 480, 15), mode(kYuyv, 1280, 720, 5),
                                          mode(kYuyv, 1280, 720, 10)};
  const auto chosen = choose_mode(modes, {});
  ASSERT_TRUE(chosen);
  EXPECT_EQ(*chosen, mode(kYuyv, 1280, 720, 10));
}

TEST(ChooseMode, WidthAloneConstrainsWidth) {
  const auto chosen = choose_mode(webcam(), {1920, 0, 0, ""});
  ASSERT_TRUE(chosen);
  EXPECT_EQ(*chosen, mode(kMjpg, 1920, 1080, 30));
}

TEST(ChooseMode, FractionalIntervals) {
  const CaptureMode ntsc{kMjpg, 1280, 720, 1001, 30000};
  EXPECT_NEAR(ntsc.fps(), 29.97, 0.001);
  const auto chosen = choose_mode({ntsc}, {0, 0, 30, ""});
  ASSERT_TRUE(chosen);
  EXPECT_EQ(*chosen, ntsc);
}

TEST(DescribeMode, ReadableText) {
  EXPECT_EQ(describe_mode(mode(kMjpg, 1280, 720, 30)), "MJPG 1280x720 @ 30 fps");
  EXPECT_EQ(describe_request({}), "any mode");
  EXPECT_EQ(describe_request({1280, 720, 60, "YUYV"}), "YUYV 1280x720 @ 60 fps");
}

}  // namespace
}  // namespace rostro::capture
