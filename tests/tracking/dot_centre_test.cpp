// A dot's measured centre is where the dot is, not pulled toward what lies beside it: a
// shading gradient across it, the dark eye slit and the iris beside a lid dot, a shadow
// beside an inner brow dot. Dots are drawn with exact pixel coverage (16x16 samples per
// pixel), so the true centre is known to a hundredth of a pixel, then blurred a little as a
// lens and a video codec would.

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <opencv2/imgproc.hpp>

#include "tracking/dot_detector.hpp"

namespace {

using namespace rostro::tracking;

// Grey level of the scene without the dot at a point.
using Background = std::function<double(double x, double y)>;

struct Ellipse {
  cv::Point2d centre;
  double semi_x = 4, semi_y = 4;  // semi-axes before rotation
  double angle = 0;               // radians
  bool contains(double x, double y) const {
    const double dx = x - centre.x, dy = y - centre.y;
    const double c = std::cos(angle), s = std::sin(angle);
    const double u = (c * dx + s * dy) / semi_x, v = (-s * dx + c * dy) / semi_y;
    return u * u + v * v <= 1;
  }
};

// The background with an ink ellipse over it, each pixel the exact mean over its area
// (16x16 samples), then a Gaussian blur of `blur` pixels and fixed-seed noise.
cv::Mat render(cv::Size size, const Background& background, const Ellipse& dot, double ink,
               double blur = 0.7, double noise = 1.0) {
  constexpr int kSamples = 16;
  cv::Mat image(size, CV_32F);
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x) {
      double sum = 0;
      for (int j = 0; j < kSamples; ++j)
        for (int i = 0; i < kSamples; ++i) {
          // Pixel (x, y) covers [x - 0.5, x + 0.5): its centre is at integer coordinates.
          const double sx = x - 0.5 + (i + 0.5) / kSamples, sy = y - 0.5 + (j + 0.5) / kSamples;
          sum += dot.contains(sx, sy) ? ink : background(sx, sy);
        }
      image.at<float>(y, x) = static_cast<float>(sum / (kSamples * kSamples));
    }
  if (blur > 0) cv::GaussianBlur(image, image, {0, 0}, blur);
  if (noise > 0) {
    cv::Mat n(size, CV_32F);
    cv::RNG rng(12345);
    rng.fill(n, cv::RNG::NORMAL, 0, noise);
    image += n;
  }
  cv::Mat out;
  image.convertTo(out, CV_8U);
  return out;
}

// Worst centre error over a few sub-pixel placements of the dot around `at`.
double worst_error(cv::Size size, const Background& background, Ellipse dot, double ink,
                   cv::Point2d at) {
  double worst = 0;
  const cv::Point2d offsets[] = {{0, 0}, {0.25, 0.5}, {0.5, 0.25}, {0.75, 0.75}, {0.4, 0.9}};
  for (const cv::Point2d& o : offsets) {
    dot.centre = at + o;
    const cv::Mat image = render(size, background, dot, ink);
    auto found = refine_dot(image, dot.centre, 2, DotOptions{});
    if (!found) return std::numeric_limits<double>::infinity();
    worst = std::max(worst, cv::norm(found->center - dot.centre));
  }
  return worst;
}

TEST(DotCentre, OnPlainSkin) {
  const Background skin = [](double, double) { return 200.0; };
  EXPECT_LT(worst_error({60, 60}, skin, Ellipse{{}, 4.5, 4.5}, 25, {30, 30}), 0.06);
  // Small dots (the closed loop's 640x480 renders them about 5 px wide).
  EXPECT_LT(worst_error({60, 60}, skin, Ellipse{{}, 2.6, 2.6}, 25, {30, 30}), 0.06);
}

TEST(DotCentre, OnAShadingGradient) {
  // Skin falling from 230 to about 110 across the dot's window: one background level for the
  // whole window weighs the rim on the lit side less than on the dark side.
  const Background shaded = [](double x, double) { return 230.0 - 3.0 * x; };
  EXPECT_LT(worst_error({40, 40}, shaded, Ellipse{{}, 4.5, 4.5}, 25, {20, 20}), 0.08);
  const Background shaded_up = [](double, double y) { return 110.0 + 3.0 * y; };
  EXPECT_LT(worst_error({40, 40}, shaded_up, Ellipse{{}, 3.5, 2.5, 0.4}, 25, {20, 20}), 0.08);
}

TEST(DotCentre, BesideTheEyeSlit) {
  // A lower-lid dot: the dark slit (lashes, iris) a pixel above its top edge, skin below,
  // and a shaded lid.
  const Background lid = [](double x, double y) {
    if (y < 24.5 && x > 12 && x < 48) return 55.0;
    return 190.0 - 1.5 * (y - 24.5);
  };
  EXPECT_LT(worst_error({60, 60}, lid, Ellipse{{}, 5, 4.2}, 25, {30, 29.5}), 0.1);
  // Touching it: the dot's top rim runs into the slit.
  EXPECT_LT(worst_error({60, 60}, lid, Ellipse{{}, 5, 4.2}, 25, {30, 28.5}), 0.12);
}

TEST(DotCentre, OverTheIrisEdge) {
  // An upper-lid dot overlapping the top of the iris (darker than skin, lighter than ink),
  // with the bright white of the eye beside the iris.
  const cv::Point2d iris(30, 38);
  const Background eye = [iris](double x, double y) {
    if (std::hypot(x - iris.x, y - iris.y) < 8) return 90.0;
    if (y > 33 && std::abs(x - iris.x) < 20) return 235.0;
    return 185.0;
  };
  EXPECT_LT(worst_error({60, 60}, eye, Ellipse{{}, 5, 4.5}, 25, {29.5, 26.5}), 0.12);
}

TEST(DotCentre, BesideAShadow) {
  // An inner brow dot beside the dark fold between the brows: a soft shadow on one side.
  const Background fold = [](double x, double) {
    return 200.0 - 110.0 / (1.0 + std::exp(-(x - 38.0) / 1.5));
  };
  EXPECT_LT(worst_error({60, 60}, fold, Ellipse{{}, 4.5, 4.5}, 25, {29.5, 30}), 0.08);
}

TEST(DotCentre, ABrightPixelAtTheCoreDoesNotHideTheDot) {
  // A faint dot in sensor noise (the low-light photo scene: contrast about 20, noise 5): the
  // pixel where the smoothed contrast peaks can itself be well under the peak, below the
  // core's level (0.9 of it). Here one pixel at the centre of a dot of contrast 24 is at 14.
  const Background skin = [](double, double) { return 60.0; };
  for (const cv::Point2d at : {cv::Point2d{30, 30}, {30.4, 29.7}}) {
    cv::Mat image = render({60, 60}, skin, Ellipse{at, 3.5, 3.5}, 36, 0.5, 0);
    const cv::Point core(static_cast<int>(std::lround(at.x)), static_cast<int>(std::lround(at.y)));
    image.at<uint8_t>(core) = 46;
    auto found = refine_dot(image, at, 3, DotOptions{});
    ASSERT_TRUE(found) << "dot at " << at;
    EXPECT_LT(cv::norm(found->center - at), 0.3) << "dot at " << at;
  }
}

}  // namespace
