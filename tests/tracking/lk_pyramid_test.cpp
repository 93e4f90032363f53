// LkPyramid: derivatives filled only around the followed points must be exactly OpenCV's
// there, and LK on it must give exactly what LK on cv::buildOpticalFlowPyramid gives.

#include "tracking/lk_pyramid.hpp"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>
#include <random>

namespace {

using rostro::tracking::LkPyramid;

cv::Mat textured(int seed, cv::Size size) {
  cv::Mat noise(size, CV_8UC1);
  cv::RNG rng(static_cast<uint64_t>(seed));
  rng.fill(noise, cv::RNG::UNIFORM, 0, 256);
  cv::Mat out;
  cv::GaussianBlur(noise, out, {0, 0}, 2.0);
  cv::normalize(out, out, 0, 255, cv::NORM_MINMAX);
  return out;
}

// Compares `sparse`'s derivatives with OpenCV's for `image` in the window LK reads around each
// of `points`, at every level; returns the number of pixels compared.
long expect_opencv_derivatives(const cv::Mat& image, const LkPyramid& sparse, cv::Size window,
                               const std::vector<cv::Point2f>& points) {
  std::vector<cv::Mat> full;
  const int levels = cv::buildOpticalFlowPyramid(image, full, window, sparse.levels(), true);
  const auto& mine = sparse.as_lk_input();
  EXPECT_EQ(mine.size(), full.size());
  if (mine.size() != full.size()) return 0;
  long compared = 0;
  for (int l = 0; l <= levels; ++l) {
    const cv::Mat& a = full[static_cast<size_t>(2 * l + 1)];
    const cv::Mat& b = mine[static_cast<size_t>(2 * l + 1)];
    EXPECT_EQ(a.size(), b.size());
    EXPECT_EQ(a.type(), b.type());
    if (a.size() != b.size() || a.type() != b.type()) return 0;
    const float scale = 1.0f / static_cast<float>(1 << l);
    for (const cv::Point2f& p : points) {
      const int cx = static_cast<int>(std::floor(p.x * scale)),
                cy = static_cast<int>(std::floor(p.y * scale));
      for (int y = cy - window.height / 2; y <= cy + window.height / 2 + 1; ++y)
        for (int x = cx - window.width / 2; x <= cx + window.width / 2 + 1; ++x) {
          if (x < 0 || y < 0 || x >= a.cols || y >= a.rows) continue;
          if (a.at<cv::Vec2s>(y, x) != b.at<cv::Vec2s>(y, x)) {
            ADD_FAILURE() << "level " << l << " at " << x << "," << y;
            return compared;
          }
          ++compared;
        }
    }
  }
  return compared;
}

TEST(LkPyramid, DerivativesAroundPointsEqualOpenCvs) {
  const cv::Mat image = textured(1, {203, 151});  // odd sizes: uneven pyramid levels
  const cv::Size window(13, 13);
  LkPyramid sparse;
  sparse.build(image, window, 2);
  ASSERT_EQ(sparse.levels(), 2);
  // Points in the middle, near every edge and in a corner (reflected borders).
  const std::vector<cv::Point2f> points = {
      {100.3f, 70.8f}, {1.2f, 75.0f}, {201.7f, 3.4f}, {0.0f, 0.0f}, {150.5f, 149.9f}};
  sparse.derivatives(points);
  EXPECT_GT(expect_opencv_derivatives(image, sparse, window, points), 1000);
}

// Pixels already filled are skipped until the next build: windows that overlap the filled ones
// must still come out whole, and a rebuild from another image must refill everything.
TEST(LkPyramid, DerivativesStayExactAcrossOverlapsAndRebuilds) {
  const cv::Mat first = textured(3, {203, 151}), second = textured(4, {203, 151});
  const cv::Size window(13, 13);
  const std::vector<cv::Point2f> points = {{60.2f, 50.5f}, {66.9f, 53.1f}, {140.0f, 90.0f}};
  const std::vector<cv::Point2f> moved = {{61.7f, 49.2f}, {70.4f, 58.8f}, {2.5f, 148.0f}};
  LkPyramid sparse;
  sparse.build(first, window, 2);
  sparse.derivatives(points);
  sparse.derivatives(moved);  // part already filled, part new
  EXPECT_GT(expect_opencv_derivatives(first, sparse, window, moved), 1000);
  sparse.build(second, window, 2);  // same size: the buffers are kept, their contents stale
  sparse.derivatives(moved);
  EXPECT_GT(expect_opencv_derivatives(second, sparse, window, moved), 1000);
}

TEST(LkPyramid, LucasKanadeGivesOpenCvsAnswer) {
  const cv::Mat first = textured(2, {240, 180});
  cv::Mat second;
  const cv::Matx23d shift(1, 0, 4.3, 0, 1, -2.6);
  cv::warpAffine(first, second, shift, first.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT);
  const cv::Size window(13, 13);
  std::vector<cv::Point2f> points;
  for (int k = 0; k < 20; ++k)
    points.emplace_back(30.0f + 9.1f * static_cast<float>(k),
                        40.0f + 5.3f * static_cast<float>(k % 7));
  std::vector<cv::Mat> a, b;
  cv::buildOpticalFlowPyramid(first, a, window, 2, true);
  cv::buildOpticalFlowPyramid(second, b, window, 2, true);
  std::vector<cv::Point2f> expected;
  std::vector<uchar> status_expected, status;
  std::vector<float> err;
  cv::calcOpticalFlowPyrLK(a, b, points, expected, status_expected, err, window, 2);

  LkPyramid pa, pb;
  pa.build(first, window, 2);
  pb.build(second, window, 2);
  pa.derivatives(points);
  std::vector<cv::Point2f> got;
  cv::calcOpticalFlowPyrLK(pa.as_lk_input(), pb.as_lk_input(), points, got, status, err, window, 2);
  ASSERT_EQ(got.size(), expected.size());
  for (size_t k = 0; k < got.size(); ++k) {
    EXPECT_EQ(status[k], status_expected[k]);
    EXPECT_FLOAT_EQ(got[k].x, expected[k].x) << k;
    EXPECT_FLOAT_EQ(got[k].y, expected[k].y) << k;
    if (status[k]) {
      EXPECT_NEAR(got[k].x - points[k].x, 4.3, 0.1) << k;
    }
  }
}

}  // namespace
