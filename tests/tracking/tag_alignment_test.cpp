#include "tracking/tag_alignment.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <random>

#include "tracking/apriltag_detector.hpp"

namespace rostro::tracking {
namespace {

constexpr int kId = 7;
constexpr int kBlack = 8;  // tag36h11's black square, in bit cells

// A tag (tag36h11 unless said) drawn on skin-grey with its black square's corners at `corners`
// (pixel centres at integer coordinates), each pixel the area average of 8x8 point samples: the
// corners are known to well under a hundredth of a pixel.
cv::Mat draw_tag(const std::array<cv::Point2d, 4>& corners, cv::Size size,
                 const std::string& family = "tag36h11", int id = kId) {
  const cv::Mat bits = apriltag_image(family, id);
  const int black = apriltag_black_width(family);
  const int border = (bits.cols - black) / 2;
  // Pattern cells (from the black square's top-left corner) to image pixels.
  const float b = static_cast<float>(black);
  std::vector<cv::Point2f> cells = {{0, b}, {b, b}, {b, 0}, {0, 0}}, image;
  for (const auto& c : corners) image.emplace_back(c);
  const cv::Matx33d to_cells(cv::getPerspectiveTransform(image, cells));
  constexpr int kFine = 8;
  cv::Mat1f fine(size.height * kFine, size.width * kFine);
  for (int y = 0; y < fine.rows; ++y)
    for (int x = 0; x < fine.cols; ++x) {
      const cv::Vec3d p = to_cells * cv::Vec3d((x + 0.5) / kFine - 0.5, (y + 0.5) / kFine - 0.5, 1);
      const int col = static_cast<int>(std::floor(p[0] / p[2])) + border;
      const int row = static_cast<int>(std::floor(p[1] / p[2])) + border;
      float v = 150;  // skin
      if (col >= 0 && row >= 0 && col < bits.cols && row < bits.rows)
        v = bits.at<uint8_t>(row, col) > 127 ? 225.0f : 35.0f;
      fine(y, x) = v;
    }
  cv::Mat1f coarse;
  cv::resize(fine, coarse, size, 0, 0, cv::INTER_AREA);
  cv::Mat out;
  coarse.convertTo(out, CV_8U);
  return out;
}

std::array<cv::Point2d, 4> tilted_square(cv::Point2d centre, double side, double angle,
                                         double keystone) {
  std::array<cv::Point2d, 4> c;
  const cv::Point2d local[4] = {{-1, 1}, {1, 1}, {1, -1}, {-1, -1}};
  for (int k = 0; k < 4; ++k) {
    // A far edge a little shorter than the near one: the tag seen from below.
    const double x = local[k].x * (1 - keystone * local[k].y), y = local[k].y;
    c[k] = centre + side / 2 *
                        cv::Point2d(x * std::cos(angle) - y * std::sin(angle),
                                    x * std::sin(angle) + y * std::cos(angle));
  }
  return c;
}

double worst_corner_error(const std::array<cv::Point2d, 4>& a,
                          const std::array<cv::Point2d, 4>& b) {
  double worst = 0;
  for (int k = 0; k < 4; ++k) worst = std::max(worst, cv::norm(a[k] - b[k]));
  return worst;
}

void add_noise(cv::Mat& image, double sigma, unsigned seed) {
  cv::Mat noise(image.size(), CV_16S);
  cv::setRNGSeed(static_cast<int>(seed));
  cv::randn(noise, 0, sigma);
  cv::Mat wide;
  image.convertTo(wide, CV_16S);
  wide += noise;
  wide.convertTo(image, CV_8U);
}

TagAligner aligner() {
  return TagAligner(apriltag_image("tag36h11", kId), kBlack);
}

// The corners libapriltag finds, aligned: over a dozen sub-pixel placements, sizes and tilts,
// with sensor noise, each corner within 0.08 px, and on average less than half as far off as
// libapriltag's own.
TEST(TagAlignment, CornersFromThePatternBeatTheSquaresEdges) {
  AprilTagDetector detector({.decimation = 1.0f});
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> frac(0, 1);
  double worst_aligned = 0, sum_aligned = 0, sum_detected = 0;
  int n = 0;
  for (int trial = 0; trial < 12; ++trial) {
    const double side = 26 + 4 * trial;  // 26-70 px: a headband tag at 640x480 to 1280x720
    const auto truth = tilted_square({80 + frac(rng), 80 + frac(rng)}, side,
                                     0.3 * (frac(rng) - 0.5), 0.08 * (frac(rng) - 0.5));
    cv::Mat image = draw_tag(truth, {160, 160});
    add_noise(image, 2.0, trial);
    const auto found = detector.detect(image);
    ASSERT_EQ(found.size(), 1u) << "trial " << trial;
    const auto aligned = aligner().align(image, found[0].corners);
    ASSERT_TRUE(aligned) << "trial " << trial;
    const double e = worst_corner_error(*aligned, truth);
    std::printf("trial %d side %.0f aligned %.3f detected %.3f\n", trial, side, e,
                worst_corner_error(found[0].corners, truth));
    worst_aligned = std::max(worst_aligned, e);
    sum_aligned += e, sum_detected += worst_corner_error(found[0].corners, truth), ++n;
  }
  EXPECT_LT(worst_aligned, 0.08);
  EXPECT_LT(sum_aligned / n, 0.5 * sum_detected / n)
      << "aligned " << sum_aligned / n << " px, libapriltag " << sum_detected / n << " px";
}

// An out-of-focus camera: the pattern is softened to match, so blur pulls no corner. From
// libapriltag's corners, each within 0.15 px and on average nearer than those.
TEST(TagAlignment, BlurredTagsAlignBetterThanTheSquaresEdges) {
  AprilTagDetector detector({.decimation = 1.0f});
  double sum_aligned = 0, sum_detected = 0;
  for (const double blur : {0.6, 1.2, 2.0})
    for (const double side : {34.0, 52.0}) {
      const auto truth = tilted_square({60.3, 61.7}, side, 0.1, 0.03);
      cv::Mat image = draw_tag(truth, {120, 120});
      cv::GaussianBlur(image, image, {0, 0}, blur);
      add_noise(image, 2.0, 1);
      const auto found = detector.detect(image);
      ASSERT_EQ(found.size(), 1u) << "blur " << blur << ", side " << side;
      const auto aligned = aligner().align(image, found[0].corners);
      ASSERT_TRUE(aligned) << "blur " << blur << ", side " << side;
      const double e = worst_corner_error(*aligned, truth);
      EXPECT_LT(e, 0.15) << "blur " << blur << ", side " << side;
      sum_aligned += e, sum_detected += worst_corner_error(found[0].corners, truth);
    }
  EXPECT_LT(sum_aligned, sum_detected);
}

// Other families: a smaller code (tag25h9) and one whose code runs outside the square
// libapriltag's corners outline (tagStandard41h12, a reversed border).
TEST(TagAlignment, OtherFamiliesAlign) {
  for (const std::string family : {"tag25h9", "tagStandard41h12"}) {
    const auto truth = tilted_square({60.4, 59.7}, 36, 0.15, 0.03);
    cv::Mat image = draw_tag(truth, {120, 120}, family, 3);
    add_noise(image, 2.0, 5);
    std::array<cv::Point2d, 4> start = truth;
    for (auto& c : start) c += cv::Point2d(0.5, -0.4);
    TagAligner aligner(apriltag_image(family, 3), apriltag_black_width(family));
    const auto aligned = aligner.align(image, start);
    ASSERT_TRUE(aligned) << family;
    EXPECT_LT(worst_corner_error(*aligned, truth), 0.08) << family;
  }
}

TEST(TagAlignment, StartsUpToAPixelOff) {
  const auto truth = tilted_square({60.6, 59.2}, 40, -0.2, 0.0);
  const cv::Mat image = draw_tag(truth, {120, 120});
  TagAligner pattern = aligner();
  for (const cv::Point2d off : {cv::Point2d(0.9, 0), cv::Point2d(0, -0.9), cv::Point2d(0.6, 0.6)}) {
    std::array<cv::Point2d, 4> start = truth;
    for (int k = 0; k < 4; ++k) start[k] += (k % 2 ? off : -off * 0.5);
    const auto aligned = pattern.align(image, start, 2.0);
    ASSERT_TRUE(aligned) << off;
    EXPECT_LT(worst_corner_error(*aligned, truth), 0.03) << off;
  }
}

TEST(TagAlignment, APartlyHiddenTagIsNotAligned) {
  const auto truth = tilted_square({60, 60}, 40, 0.05, 0.0);
  cv::Mat image = draw_tag(truth, {120, 120});
  cv::rectangle(image, cv::Point(40, 55), cv::Point(90, 100), cv::Scalar(150), cv::FILLED);
  EXPECT_FALSE(aligner().align(image, truth));
}

TEST(TagAlignment, NoTagThereIsNotAligned) {
  const cv::Mat image(120, 120, CV_8UC1, cv::Scalar(150));
  EXPECT_FALSE(aligner().align(image, tilted_square({60, 60}, 40, 0, 0)));
}

TEST(TagAlignment, ATagAtTheImageEdgeIsNotAligned) {
  const auto truth = tilted_square({18, 60}, 40, 0, 0);
  const cv::Mat image = draw_tag(truth, {120, 120});
  EXPECT_FALSE(aligner().align(image, truth));
}

}  // namespace
}  // namespace rostro::tracking
