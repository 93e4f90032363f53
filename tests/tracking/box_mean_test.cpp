// box3_mean: the dot detector's 3x3 mean over part of a contrast window must equal
// cv::blur(src, dst, {3, 3}) there to the bit (the tracks must not change with it), in the
// middle, along every edge and in the corners (reflected borders), and must leave the rest
// of the output alone.

#include "tracking/box_mean.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <opencv2/imgproc.hpp>

namespace {

using rostro::tracking::box3_mean;

// A contrast window as the detector makes it: grey levels minus a median grey level, whole
// numbers from -255 to 255.
cv::Mat contrast_window(cv::Size size, uint64_t seed) {
  cv::Mat grey(size, CV_8UC1);
  cv::RNG rng(seed);
  rng.fill(grey, cv::RNG::UNIFORM, 0, 256);
  cv::Mat out;
  grey.convertTo(out, CV_32F, -1.0, static_cast<double>(rng.uniform(0, 256)));
  return out;
}

bool same_bits(float a, float b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

TEST(BoxMean, EqualsOpenCvBlurToTheBitEverywhere) {
  long compared = 0;
  for (const cv::Size size : {cv::Size(45, 45), cv::Size(5, 7), cv::Size(31, 12), cv::Size(1, 9)}) {
    const cv::Mat c = contrast_window(size, static_cast<uint64_t>(size.area()));
    cv::Mat expected;
    cv::blur(c, expected, {3, 3});
    cv::Mat mine(c.size(), CV_32F, cv::Scalar(-1e6));
    box3_mean(c, mine, {0, 0, c.cols, c.rows});
    for (int y = 0; y < c.rows; ++y)
      for (int x = 0; x < c.cols; ++x, ++compared)
        ASSERT_TRUE(same_bits(mine.at<float>(y, x), expected.at<float>(y, x)))
            << size << " at " << x << "," << y << ": " << mine.at<float>(y, x) << " vs "
            << expected.at<float>(y, x);
  }
  EXPECT_GT(compared, 2000);
}

TEST(BoxMean, FillsOnlyTheAreaAskedForClippedToTheImage) {
  const cv::Mat c = contrast_window({45, 45}, 7);
  cv::Mat expected;
  cv::blur(c, expected, {3, 3});
  constexpr float kUntouched = -12345.f;
  // One area inside, one reaching past the top-left corner and one past the bottom-right
  // (clipped there).
  for (const cv::Rect area :
       {cv::Rect(15, 17, 13, 13), cv::Rect(-4, -3, 10, 9), cv::Rect(38, 40, 12, 12)}) {
    cv::Mat mine(c.size(), CV_32F, cv::Scalar(kUntouched));
    box3_mean(c, mine, area);
    const cv::Rect inside = area & cv::Rect(0, 0, c.cols, c.rows);
    for (int y = 0; y < c.rows; ++y)
      for (int x = 0; x < c.cols; ++x) {
        if (inside.contains({x, y}))
          ASSERT_TRUE(same_bits(mine.at<float>(y, x), expected.at<float>(y, x))) << x << "," << y;
        else
          ASSERT_EQ(mine.at<float>(y, x), kUntouched) << x << "," << y;
      }
  }
}

}  // namespace
