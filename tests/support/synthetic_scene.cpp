#include "tests/support/synthetic_scene.hpp"

#include <cmath>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <random>

#include "tracking/apriltag_detector.hpp"

namespace rostro::tracking::testing {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr float kSkin = 175, kInk = 45;

cv::Point2d apply(const cv::Matx23d& m, cv::Point2d p) {
  return {m(0, 0) * p.x + m(0, 1) * p.y + m(0, 2), m(1, 0) * p.x + m(1, 1) * p.y + m(1, 2)};
}

// Exact-enough disc coverage: 8x8 samples in each pixel the edge crosses.
void draw_disc(cv::Mat& image, cv::Point2d c, double r, float ink) {
  const int x0 = static_cast<int>(std::floor(c.x - r - 1)),
            x1 = static_cast<int>(std::ceil(c.x + r + 1));
  const int y0 = static_cast<int>(std::floor(c.y - r - 1)),
            y1 = static_cast<int>(std::ceil(c.y + r + 1));
  constexpr int s = 8;
  for (int y = std::max(0, y0); y <= std::min(image.rows - 1, y1); ++y)
    for (int x = std::max(0, x0); x <= std::min(image.cols - 1, x1); ++x) {
      int inside = 0;
      for (int j = 0; j < s; ++j)
        for (int i = 0; i < s; ++i) {
          const double px = x - 0.5 + (i + 0.5) / s - c.x, py = y - 0.5 + (j + 0.5) / s - c.y;
          inside += px * px + py * py <= r * r;
        }
      const float cover = static_cast<float>(inside) / (s * s);
      float& v = image.at<float>(y, x);
      v = v * (1 - cover) + ink * cover;
    }
}

}  // namespace

SyntheticScene::SyntheticScene(const MarkerLayout& layout, SceneOptions options)
    : layout_(layout), options_(std::move(options)) {
  std::mt19937 rng(options_.seed);
  std::normal_distribution<float> n(0, 1);
  cv::Mat noise(options_.size.height + 80, options_.size.width + 80, CV_32F);
  for (int y = 0; y < noise.rows; ++y)
    for (int x = 0; x < noise.cols; ++x) noise.at<float>(y, x) = n(rng);
  cv::Mat coarse, fine;
  cv::GaussianBlur(noise, coarse, {0, 0}, 6);
  cv::GaussianBlur(noise, fine, {0, 0}, 1.2);
  texture_ = kSkin + coarse * 60 + fine * 8;  // blotches and pores
}

cv::Mat SyntheticScene::render(int k, std::map<std::string, Truth>& truth) const {
  const SceneOptions& o = options_;
  // The head's similarity at frame k: frontal millimetres -> pixels.
  const double t = k;
  const double angle = (o.angle_deg + 2.0 * std::sin(t * 0.05)) * kPi / 180;
  const double scale = o.px_per_mm * (1 + 0.03 * std::sin(t * 0.037));
  const cv::Point2d centre(
      o.size.width / 2.0 + o.motion_px * std::sin(t * 0.13) + 0.1234,
      o.size.height / 2.0 + 10 + o.motion_px * 0.7 * std::cos(t * 0.09) + 0.377);
  const double c = std::cos(angle) * scale, s = std::sin(angle) * scale;
  const cv::Matx23d head(c, -s, centre.x, s, c, centre.y);

  // Skin texture moves with the head.
  cv::Matx23d tex_to_image(std::cos(angle), -std::sin(angle), 0, std::sin(angle), std::cos(angle),
                           0);
  const cv::Point2d tex_centre(texture_.cols / 2.0, texture_.rows / 2.0);
  const cv::Point2d rotated = apply(tex_to_image, tex_centre);
  tex_to_image(0, 2) = centre.x - rotated.x;
  tex_to_image(1, 2) = centre.y - rotated.y;
  cv::Mat image;
  cv::warpAffine(texture_, image, cv::Mat(tex_to_image), o.size, cv::INTER_LINEAR,
                 cv::BORDER_REFLECT);

  truth.clear();
  for (const MarkerSpec& m : layout_.markers) {
    Truth tr;
    if (m.is_tag()) {
      if (!o.draw_tags) continue;
      // The tag's bit image, 10 px per cell, mapped so its black square lands on the corners.
      cv::Mat bits = apriltag_image(m.family, m.tag_id);
      const int cell = 10;
      cv::Mat big;
      cv::resize(bits, big, {}, cell, cell, cv::INTER_NEAREST);
      big.convertTo(big, CV_32F, (kSkin + 40 - kInk) / 255.0, kInk);
      const int black = apriltag_black_width(m.family);
      const double border = (bits.cols - black) / 2.0 * cell;
      auto frontal = m.tag_corners_frontal();
      // libapriltag corner order on an upright tag: bottom-left, bottom-right, top-right, top-left.
      // Pixel centres of the bitmap sit at integers; edge positions at -0.5 + n*cell.
      const double lo = border - 0.5, hi = border + black * cell - 0.5;
      std::vector<cv::Point2f> src = {
          {float(lo), float(hi)}, {float(hi), float(hi)}, {float(hi), float(lo)}};
      std::vector<cv::Point2f> dst;
      for (int q = 0; q < 3; ++q) dst.emplace_back(apply(head, frontal[q]));
      for (int q = 0; q < 4; ++q) tr.corners[q] = apply(head, frontal[q]);
      cv::Mat a = cv::getAffineTransform(src, dst);
      cv::Mat warped, mask;
      cv::warpAffine(big, warped, a, o.size, cv::INTER_LINEAR, cv::BORDER_CONSTANT, 0);
      cv::Mat ones(big.size(), CV_32F, 1.0f);
      cv::warpAffine(ones, mask, a, o.size, cv::INTER_LINEAR, cv::BORDER_CONSTANT, 0);
      image = image.mul(1 - mask) + warped.mul(mask);
      tr.position = apply(head, m.frontal());
    } else {
      cv::Point2d own(0, 0);
      const int g = m.feature_point.group;
      if (g == 8 || g == 2)
        own = {0, o.expression_px * std::sin(t * 0.21 + m.position_mm.x * 0.05)};
      if (g == 4) own = {0, -o.expression_px * 0.6 * std::sin(t * 0.17)};
      tr.position = apply(head, m.frontal()) + own;
      draw_disc(image, tr.position, o.dot_diameter_px / 2, kInk);
    }
    const double edge = m.is_tag() ? m.size_mm * o.px_per_mm * 0.75 : o.dot_diameter_px;
    tr.visible = tr.position.x > edge && tr.position.y > edge &&
                 tr.position.x < o.size.width - 1 - edge &&
                 tr.position.y < o.size.height - 1 - edge;
    truth[m.id] = tr;
  }

  // Occluders: a flat, slightly textured "hand" over the face.
  for (const Occluder& oc : o.occluders) {
    if (k < oc.first || k > oc.last) continue;
    cv::Rect r(
        cv::Point(static_cast<int>(std::floor(oc.rect.x)), static_cast<int>(std::floor(oc.rect.y))),
        cv::Point(static_cast<int>(std::ceil(oc.rect.br().x)),
                  static_cast<int>(std::ceil(oc.rect.br().y))));
    r &= cv::Rect(0, 0, o.size.width, o.size.height);
    image(r) = 140.0f;
    const double margin = o.dot_diameter_px / 2 + 2 * o.blur_sigma + 1;
    const double radius = o.dot_diameter_px / 2;
    for (auto& [id, tr] : truth) {
      const double extent =
          layout_.find(id)->is_tag() ? layout_.find(id)->size_mm * o.px_per_mm : margin;
      cv::Rect2d grown(oc.rect.x - extent, oc.rect.y - extent, oc.rect.width + 2 * extent,
                       oc.rect.height + 2 * extent);
      if (grown.contains(tr.position)) tr.visible = false;
      cv::Rect2d inner(oc.rect.x + radius, oc.rect.y + radius, oc.rect.width - 2 * radius,
                       oc.rect.height - 2 * radius);
      if (inner.contains(tr.position)) tr.hidden = true;
    }
  }

  if (o.blur_sigma > 0) cv::GaussianBlur(image, image, {0, 0}, o.blur_sigma);
  if (o.noise_sigma > 0) {
    cv::Mat noise(image.size(), CV_32F);
    cv::RNG rng(o.seed * 1000u + static_cast<unsigned>(k));
    rng.fill(noise, cv::RNG::NORMAL, 0, o.noise_sigma);
    image += noise;
  }
  cv::Mat out;
  image.convertTo(out, CV_8U);
  return out;
}

}  // namespace rostro::tracking::testing
