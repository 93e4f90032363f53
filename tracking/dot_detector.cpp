#include "tracking/dot_detector.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <opencv2/imgproc.hpp>

namespace rostro::tracking {
namespace {

constexpr double kPi = std::numbers::pi;

// Contrast of each pixel against `background`, positive for the expected polarity.
inline float contrast_of(DotPolarity polarity, float background, float value) {
  return polarity == DotPolarity::Dark ? background - value : value - background;
}

// Median grey level of the window's border: the background around a dot in the middle.
float border_median(const cv::Mat& patch) {
  std::vector<uint8_t> v;
  v.reserve(static_cast<size_t>(2 * (patch.cols + patch.rows)));
  for (int x = 0; x < patch.cols; ++x) {
    v.push_back(patch.at<uint8_t>(0, x));
    v.push_back(patch.at<uint8_t>(patch.rows - 1, x));
  }
  for (int y = 1; y + 1 < patch.rows; ++y) {
    v.push_back(patch.at<uint8_t>(y, 0));
    v.push_back(patch.at<uint8_t>(y, patch.cols - 1));
  }
  auto mid = v.begin() + static_cast<long>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// The blob connected to `peak` where the contrast is at least `threshold`.
struct Extent {
  cv::Mat region;  // 0/255, the patch's size
  double area = 0;
  double diameter = 0;  // equivalent-area
  // Area over the area of the smallest ellipse of the blob's own orientation and aspect
  // that holds it: a disc seen at an angle is an ellipse and as round as one seen square on.
  double roundness = 0;
  double elongation = 1;  // long axis / short axis
  bool touches_edge = false;
  cv::Point2d centre;
};

Extent extent_at(const cv::Mat& c, cv::Point peak, float threshold) {
  Extent e;
  cv::Mat above = c >= threshold;
  cv::Mat region = cv::Mat::zeros(c.rows + 2, c.cols + 2, CV_8U);
  cv::floodFill(above, region, peak, 255, nullptr, 0, 0, 4 | cv::FLOODFILL_MASK_ONLY | (255 << 8));
  e.region = region(cv::Rect(1, 1, c.cols, c.rows)).clone();
  e.area = cv::countNonZero(e.region);
  if (e.area <= 0) return e;
  const cv::Moments mo = cv::moments(e.region, true);
  e.centre = {mo.m10 / mo.m00, mo.m01 / mo.m00};
  // Principal axes of the blob (pixels as unit squares: + 1/12 each way).
  const double sxx = mo.mu20 / mo.m00 + 1.0 / 12, syy = mo.mu02 / mo.m00 + 1.0 / 12,
               sxy = mo.mu11 / mo.m00;
  const double mean = (sxx + syy) / 2,
               spread = std::sqrt((sxx - syy) * (sxx - syy) / 4 + sxy * sxy);
  const double l1 = mean + spread, l2 = std::max(mean - spread, 1e-6);
  const double angle = 0.5 * std::atan2(2 * sxy, sxx - syy);
  const double ca = std::cos(angle), sa = std::sin(angle);
  const double a = std::sqrt(l1), b = std::sqrt(l2);
  e.elongation = a / b;
  double far = 0;  // largest normalised ellipse radius of a pixel
  for (int y = 0; y < e.region.rows; ++y) {
    const uint8_t* r = e.region.ptr<uint8_t>(y);
    for (int x = 0; x < e.region.cols; ++x) {
      if (!r[x]) continue;
      if (x == 0 || y == 0 || x == e.region.cols - 1 || y == e.region.rows - 1)
        e.touches_edge = true;
      const double dx = x - e.centre.x, dy = y - e.centre.y;
      const double u = (ca * dx + sa * dy) / a, v = (-sa * dx + ca * dy) / b;
      far = std::max(far, std::sqrt(u * u + v * v));
    }
  }
  e.diameter = 2 * std::sqrt(e.area / kPi);
  e.roundness = e.area / (kPi * (far * a + 0.5) * (far * b + 0.5));
  return e;
}

// Shares of the peak contrast at which a dot's extent is measured, lowest first.
constexpr double kExtentLevels[] = {0.5, 0.6, 0.7, 0.8, 0.9};

}  // namespace

std::optional<Dot> refine_dot(const cv::Mat& gray, cv::Point2d guess, double radius,
                              const DotOptions& options) {
  CV_Assert(gray.type() == CV_8UC1);
  const double max_r = options.max_diameter_px / 2;
  const int half = static_cast<int>(std::ceil(radius + max_r + 2));
  const cv::Rect image_rect(0, 0, gray.cols, gray.rows);
  const cv::Rect window =
      cv::Rect(static_cast<int>(std::lround(guess.x)) - half,
               static_cast<int>(std::lround(guess.y)) - half, 2 * half + 1, 2 * half + 1) &
      image_rect;
  if (window.width < 5 || window.height < 5) return std::nullopt;
  const cv::Mat patch = gray(window);
  const float background = border_median(patch);

  // Contrast map of the window.
  cv::Mat c(patch.size(), CV_32F);
  for (int y = 0; y < patch.rows; ++y) {
    const uint8_t* in = patch.ptr<uint8_t>(y);
    float* out = c.ptr<float>(y);
    for (int x = 0; x < patch.cols; ++x) out[x] = contrast_of(options.polarity, background, in[x]);
  }
  cv::Mat smooth;
  cv::blur(c, smooth, {3, 3});

  // The strongest point within `radius` of the guess is the dot's core.
  const cv::Point2d g(guess.x - window.x, guess.y - window.y);
  cv::Point peak(-1, -1);
  float peak_value = -1e9f;
  for (int y = 0; y < smooth.rows; ++y)
    for (int x = 0; x < smooth.cols; ++x) {
      const double dx = x - g.x, dy = y - g.y;
      if (dx * dx + dy * dy > radius * radius) continue;
      if (smooth.at<float>(y, x) > peak_value) peak_value = smooth.at<float>(y, x), peak = {x, y};
    }
  if (peak.x < 0 || peak_value < options.min_contrast) return std::nullopt;

  // Its extent: the pixels connected to the peak above a share of the peak. Half is the
  // dot's true edge on plain skin. A dot that touches a darker feature (an eyebrow, the
  // iris, a nostril, the shadow under the chin) merges with it at half; those features are
  // lighter than the dot's core, so at a higher share the dot stands alone. A lone dot's
  // edge is steep: its size hardly changes with the share, where a merged blob's jumps.
  // The lowest share whose blob is no wider than the core's plus its rim is the dot.
  const Extent core = extent_at(c, peak, static_cast<float>(kExtentLevels[4] * peak_value));
  if (core.area <= 0 || core.touches_edge) return std::nullopt;
  const double rim = std::max(1.5, 0.2 * core.diameter);
  Extent extent;
  double share = 0;
  for (double level : kExtentLevels) {
    extent = level == kExtentLevels[4] ? core
                                       : extent_at(c, peak, static_cast<float>(level * peak_value));
    if (!extent.touches_edge && extent.diameter <= core.diameter + rim) {
      share = level;
      break;
    }
  }
  if (share == 0) return std::nullopt;
  // Above half the blob is smaller than the dot: its rim (the anti-aliased edge, about a
  // pixel wide) is added back so the reported size does not depend on the share.
  const double diameter = share > kExtentLevels[0]
                              ? extent.diameter + (share - kExtentLevels[0]) * 2.5
                              : extent.diameter;
  if (diameter < options.min_diameter_px || diameter > options.max_diameter_px ||
      extent.roundness < options.min_roundness || extent.elongation > options.max_elongation)
    return std::nullopt;
  cv::Point2d centre = extent.centre;

  // Contrast-weighted centroid over a disc just wider than the dot, re-centred twice. The
  // small floor keeps background texture inside the disc from pulling the centre.
  const float floor = 0.15f * peak_value;
  const double disc = diameter / 2 + 2.0;
  // Beside a darker feature only the dot's own blob and its rim count: the feature's pixels
  // inside the disc would pull the centre toward it.
  cv::Mat own;
  if (share > kExtentLevels[0])
    cv::dilate(extent.region, own, cv::getStructuringElement(cv::MORPH_CROSS, {3, 3}));
  for (int iteration = 0; iteration < 3; ++iteration) {
    double sw = 0, sx = 0, sy = 0;
    const int x0 = std::max(0, static_cast<int>(centre.x - disc));
    const int x1 = std::min(c.cols - 1, static_cast<int>(centre.x + disc + 1));
    const int y0 = std::max(0, static_cast<int>(centre.y - disc));
    const int y1 = std::min(c.rows - 1, static_cast<int>(centre.y + disc + 1));
    for (int y = y0; y <= y1; ++y) {
      const float* row = c.ptr<float>(y);
      for (int x = x0; x <= x1; ++x) {
        const double dx = x - centre.x, dy = y - centre.y;
        if (dx * dx + dy * dy > disc * disc) continue;
        if (!own.empty() && !own.at<uint8_t>(y, x)) continue;
        const double w = std::clamp(row[x] - floor, 0.0f, peak_value - floor);
        sw += w, sx += w * x, sy += w * y;
      }
    }
    if (sw <= 0) return std::nullopt;
    centre = {sx / sw, sy / sw};
  }
  return Dot{{centre.x + window.x, centre.y + window.y}, diameter, peak_value};
}

std::vector<Dot> detect_dots(const cv::Mat& gray, const DotOptions& options, cv::Rect roi) {
  CV_Assert(gray.type() == CV_8UC1);
  const cv::Rect image_rect(0, 0, gray.cols, gray.rows);
  roi = roi.area() > 0 ? roi & image_rect : image_rect;
  if (roi.width < 5 || roi.height < 5) return {};
  const cv::Mat patch = gray(roi);

  // Local background: a box mean three dot-widths wide.
  int box = static_cast<int>(std::ceil(3 * options.max_diameter_px)) | 1;
  cv::Mat background;
  cv::blur(patch, background, {box, box}, {-1, -1}, cv::BORDER_REPLICATE);
  cv::Mat contrast;
  if (options.polarity == DotPolarity::Dark)
    cv::subtract(background, patch, contrast);  // saturates at 0
  else
    cv::subtract(patch, background, contrast);
  // Candidates: local maxima of the (lightly smoothed) contrast. Connected blobs of the
  // thresholded contrast are no use on a face: a dot beside a shadow (the nose, the lips,
  // the chin) merges with it into one large blob and would never be looked at.
  cv::Mat smooth;
  contrast.convertTo(smooth, CV_32F);
  cv::GaussianBlur(smooth, smooth, {5, 5}, 1.0);
  const int reach = std::max(3, static_cast<int>(options.min_diameter_px)) | 1;
  cv::Mat peaks;
  cv::dilate(smooth, peaks, cv::getStructuringElement(cv::MORPH_ELLIPSE, {reach, reach}));
  struct Candidate {
    float value;
    cv::Point at;
  };
  std::vector<Candidate> candidates;
  const float least = static_cast<float>(options.min_contrast) / 2;
  for (int y = 0; y < smooth.rows; ++y) {
    const float* s = smooth.ptr<float>(y);
    const float* p = peaks.ptr<float>(y);
    for (int x = 0; x < smooth.cols; ++x)
      if (s[x] >= least && s[x] >= p[x]) candidates.push_back({s[x], {x, y}});
  }
  std::sort(candidates.begin(), candidates.end(),
            [](const Candidate& a, const Candidate& b) { return a.value > b.value; });

  std::vector<Dot> dots;
  std::vector<cv::Point2d> tried;
  for (const Candidate& c : candidates) {
    const cv::Point2d at(c.at.x + roi.x, c.at.y + roi.y);
    // A plateau gives several maxima; a dot already measured covers its own.
    bool seen = false;
    for (const Dot& d : dots)
      if (cv::norm(d.center - at) < std::max(options.min_diameter_px / 2, d.diameter / 2 + 1))
        seen = true;
    for (const cv::Point2d& t : tried)
      if (cv::norm(t - at) < 1.5) seen = true;
    if (seen) continue;
    tried.push_back(at);
    auto dot = refine_dot(gray, at, std::max(2.0, options.min_diameter_px / 2), options);
    if (!dot) continue;
    bool duplicate = false;
    for (const Dot& d : dots)
      if (cv::norm(d.center - dot->center) < options.min_diameter_px / 2) duplicate = true;
    if (!duplicate) dots.push_back(*dot);
  }
  std::sort(dots.begin(), dots.end(),
            [](const Dot& a, const Dot& b) { return a.contrast > b.contrast; });
  return dots;
}

}  // namespace rostro::tracking
