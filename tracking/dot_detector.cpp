#include "tracking/dot_detector.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <opencv2/imgproc.hpp>

#include "facecore/option_check.hpp"
#include "tracking/box_mean.hpp"

namespace rostro::tracking {
namespace {

constexpr double kPi = std::numbers::pi;

// Contrast of each pixel against `background`, positive for the expected polarity.
inline float contrast_of(DotPolarity polarity, float background, float value) {
  return polarity == DotPolarity::Dark ? background - value : value - background;
}

// Median grey level of the window's border: the background around a dot in the middle.
float border_median(const cv::Mat& patch) {
  thread_local std::vector<uint8_t> v;  // refine_dot runs per dot per frame: no allocation
  v.clear();
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

// The strongest pixel of the 3x3 box around `at` (`at` itself on a tie).
cv::Point strongest_around(const cv::Mat& c, cv::Point at) {
  cv::Point best = at;
  float best_value = c.at<float>(at.y, at.x);
  for (int y = std::max(0, at.y - 1); y <= std::min(c.rows - 1, at.y + 1); ++y)
    for (int x = std::max(0, at.x - 1); x <= std::min(c.cols - 1, at.x + 1); ++x)
      if (c.at<float>(y, x) > best_value) best_value = c.at<float>(y, x), best = {x, y};
  return best;
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
  // The filled ellipse of the same second moments: semi-axes and the long axis's angle.
  double semi_long = 0, semi_short = 0, angle = 0;
  bool touches_edge = false;
  cv::Point2d centre;
};

// A 4-connected flood fill over the pixels at or above `threshold`, with the blob's moments
// summed as it goes: this runs a few times per dot per frame, on windows of a few hundred
// pixels, where OpenCV's compare + floodFill + moments cost more in set-up than in work.
// A blob growing past `max_area` pixels is given up (marked as touching the edge): the
// caller would reject it as too wide, and a dot merged with an eyebrow or the hair can be
// hundreds of pixels.
Extent extent_at(const cv::Mat& c, cv::Point peak, float threshold,
                 size_t max_area = std::numeric_limits<size_t>::max()) {
  Extent e;
  const int w = c.cols, h = c.rows;
  e.region = cv::Mat::zeros(h, w, CV_8U);
  if (peak.x < 0 || peak.y < 0 || peak.x >= w || peak.y >= h ||
      c.at<float>(peak.y, peak.x) < threshold)
    return e;
  thread_local std::vector<cv::Point> pixels;
  pixels.clear();
  pixels.push_back(peak);
  e.region.at<uint8_t>(peak.y, peak.x) = 255;
  const auto mark_step = static_cast<ptrdiff_t>(e.region.step1()),
             value_step = static_cast<ptrdiff_t>(c.step1());
  double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
  for (size_t k = 0; k < pixels.size(); ++k) {
    if (pixels.size() > max_area) {
      e.touches_edge = true;
      e.area = static_cast<double>(pixels.size());
      e.diameter = 2 * std::sqrt(e.area / kPi);
      return e;
    }
    const cv::Point p = pixels[k];
    sx += p.x, sy += p.y;
    sxx += static_cast<double>(p.x) * p.x, syy += static_cast<double>(p.y) * p.y,
        sxy += static_cast<double>(p.x) * p.y;
    if (p.x == 0 || p.y == 0 || p.x == w - 1 || p.y == h - 1) e.touches_edge = true;
    // The four neighbours in the same order (left, right, up, down), by pointer: this loop
    // is a tenth of a frame's tracking.
    uint8_t* mark = e.region.ptr<uint8_t>(p.y) + p.x;
    const float* value = c.ptr<float>(p.y) + p.x;
    auto visit = [&](uint8_t* m, const float* v, int qx, int qy) {
      if (*m || *v < threshold) return;
      *m = 255;
      pixels.emplace_back(qx, qy);
    };
    if (p.x > 0) visit(mark - 1, value - 1, p.x - 1, p.y);
    if (p.x + 1 < w) visit(mark + 1, value + 1, p.x + 1, p.y);
    if (p.y > 0) visit(mark - mark_step, value - value_step, p.x, p.y - 1);
    if (p.y + 1 < h) visit(mark + mark_step, value + value_step, p.x, p.y + 1);
  }
  const double n = static_cast<double>(pixels.size());
  e.area = n;
  e.centre = {sx / n, sy / n};
  // Principal axes of the blob (pixels as unit squares: + 1/12 each way).
  const double vxx = sxx / n - e.centre.x * e.centre.x + 1.0 / 12,
               vyy = syy / n - e.centre.y * e.centre.y + 1.0 / 12,
               vxy = sxy / n - e.centre.x * e.centre.y;
  const double mean = (vxx + vyy) / 2,
               spread = std::sqrt((vxx - vyy) * (vxx - vyy) / 4 + vxy * vxy);
  const double l1 = mean + spread, l2 = std::max(mean - spread, 1e-6);
  const double angle = 0.5 * std::atan2(2 * vxy, vxx - vyy);
  const double ca = std::cos(angle), sa = std::sin(angle);
  const double a = std::sqrt(l1), b = std::sqrt(l2);
  e.elongation = a / b;
  // A filled ellipse's variance along a semi-axis s is s^2 / 4.
  e.semi_long = 2 * a, e.semi_short = 2 * b, e.angle = angle;
  double far2 = 0;  // largest squared normalised ellipse radius of a pixel
  for (const cv::Point& p : pixels) {
    const double dx = p.x - e.centre.x, dy = p.y - e.centre.y;
    const double u = (ca * dx + sa * dy) / a, v = (-sa * dx + ca * dy) / b;
    far2 = std::max(far2, u * u + v * v);
  }
  const double far = std::sqrt(far2);
  e.diameter = 2 * std::sqrt(e.area / kPi);
  e.roundness = e.area / (kPi * (far * a + 0.5) * (far * b + 0.5));
  return e;
}

// Shares of the peak contrast at which a dot's extent is measured, lowest first.
constexpr double kExtentLevels[] = {0.5, 0.6, 0.7, 0.8, 0.9};

// The centre of the ellipse through a dot's edge, found along rays from `start`.
//
// Why not the centroid alone: it weighs every pixel's contrast against one background level,
// so a shading gradient across the dot, or a darker feature touching its rim (the eye slit
// and the iris beside a lid dot, the shadow beside an inner brow dot, the mouth beside a lip
// dot), pulls it by a few tenths of a pixel toward the dark side. An edge point instead is
// where the profile along its ray crosses halfway between the dot's ink just inside and
// whatever lies just outside *on that ray*: a blurred step crosses its midpoint at the step,
// whatever the level beyond it. Rays with no clear step (into the pupil, as dark as the ink)
// are dropped, and the ellipse is fitted to the rest, so a missing stretch of rim leaves the
// centre where the remaining rim puts it.
constexpr int kRays = 32;
// Surroundings whose contrast varies by less than this share of the dot's are even.
constexpr double kEvenRing = 0.1;
constexpr double kSettled = 0.1;  // pixels: a fit that moves its start less needs no second

// Unit directions of the rays, once.
const std::array<cv::Point2d, kRays>& ray_directions() {
  static const std::array<cv::Point2d, kRays> directions = [] {
    std::array<cv::Point2d, kRays> d;
    for (int k = 0; k < kRays; ++k) {
      const double angle = 2 * kPi * k / kRays;
      d[static_cast<size_t>(k)] = {std::cos(angle), std::sin(angle)};
    }
    return d;
  }();
  return directions;
}
constexpr int kMostSamples = 64;  // along one ray: a dot up to ~50 px wide
// A ray whose outside is darker than the skin by more than this share of the ink's step ran
// into a darker feature.
constexpr double kDarkerOutside = 0.15;
constexpr double kPlaneTolerance = 0.06;  // the same for the rays the skin plane is fitted to
// Outside levels that vary by less than this share of the step (or of the ink) count as flat.
constexpr float kFlatShare = 0.25f, kFlatFloor = 0.05f;
// The least step to a darker feature, as a share of the step to skin, that gives an edge.
constexpr float kLeastStepShare = 0.2f;

// Solves a x = b for a small symmetric positive-definite a (normal equations), in place by
// elimination: cv::solve would allocate, and this runs a few times per dot per frame.
template <int N>
bool solve_normal(double (&a)[N][N], double (&b)[N], double (&x)[N]) {
  for (int i = 0; i < N; ++i) {
    if (!(a[i][i] > 1e-12)) return false;
    for (int j = i + 1; j < N; ++j) {
      const double f = a[j][i] / a[i][i];
      for (int k = i; k < N; ++k) a[j][k] -= f * a[i][k];
      b[j] -= f * b[i];
    }
  }
  for (int i = N - 1; i >= 0; --i) {
    double sum = b[i];
    for (int k = i + 1; k < N; ++k) sum -= a[i][k] * x[k];
    x[i] = sum / a[i][i];
  }
  return true;
}

std::optional<cv::Point2d> fit_ellipse_centre(const std::vector<cv::Point2d>& points,
                                              cv::Point2d origin, double scale,
                                              cv::Matx<double, 5, 1>& conic) {
  // a x^2 + b xy + c y^2 + d x + e y = 1 in coordinates about `origin` scaled by 1/scale:
  // the origin lies inside the dot, so the conic's constant is never 0.
  double ata[5][5] = {}, atb[5] = {}, k[5];
  for (const cv::Point2d& p : points) {
    const double x = (p.x - origin.x) / scale, y = (p.y - origin.y) / scale;
    const double row[5] = {x * x, x * y, y * y, x, y};
    for (int i = 0; i < 5; ++i) {
      for (int j = i; j < 5; ++j) ata[i][j] += row[i] * row[j];
      atb[i] += row[i];
    }
  }
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < i; ++j) ata[i][j] = ata[j][i];
  if (!solve_normal(ata, atb, k)) return std::nullopt;
  conic = cv::Matx<double, 5, 1>(k[0], k[1], k[2], k[3], k[4]);
  const double a = conic(0), b = conic(1), c = conic(2), d = conic(3), e = conic(4);
  const double det = 4 * a * c - b * b;
  if (det <= 1e-12 || a <= 0) return std::nullopt;  // not an ellipse
  const double x = (b * e - 2 * c * d) / det, y = (b * d - 2 * a * e) / det;
  return cv::Point2d(origin.x + x * scale, origin.y + y * scale);
}

// Distance from `p` to the conic's zero set, to first order.
double conic_distance(const cv::Matx<double, 5, 1>& k, cv::Point2d p, cv::Point2d origin,
                      double scale) {
  const double x = (p.x - origin.x) / scale, y = (p.y - origin.y) / scale;
  const double f = k(0) * x * x + k(1) * x * y + k(2) * y * y + k(3) * x + k(4) * y - 1;
  const double gx = 2 * k(0) * x + k(1) * y + k(3), gy = k(1) * x + 2 * k(2) * y + k(4);
  const double g = std::hypot(gx, gy);
  return g > 0 ? std::abs(f) / g * scale : std::numeric_limits<double>::infinity();
}

// Edge points along kRays rays from `start`; `radius_at(direction)` is the dot's expected radius
// that way; nullopt when too little of the rim gives a clean edge.
template <typename RadiusAt>
std::optional<cv::Point2d> edge_ellipse_centre(const cv::Mat& c, cv::Point2d start,
                                               RadiusAt radius_at, double least_step) {
  constexpr double kStep = 0.5;     // along the ray, pixels
  constexpr double kOutside = 2.0;  // past the edge where the outside level is read: beyond the
                                    // blur, yet close enough to stay on what touches the dot
  constexpr double kBeyond = 4.0;   // past the edge where a darker feature is looked for
  struct Ray {
    double angle = 0;
    cv::Point2d u;               // direction
    float ink = 0, outside = 0;  // contrast just inside and just outside the edge
    float beyond = 0;            // the darkest a little further out
    int edge = 0, n = 0;         // steepest sample, samples
    float s[kMostSamples];       // contrast along the ray, kStep apart
  };
  thread_local std::vector<Ray> rays(kRays);
  thread_local std::vector<cv::Point2d> points;
  thread_local std::vector<double> angles;
  points.clear();
  angles.clear();
  double radius_sum = 0;
  size_t measured = 0;
  for (int k = 0; k < kRays; ++k) {
    const double angle = 2 * kPi * k / kRays;
    const cv::Point2d u = ray_directions()[static_cast<size_t>(k)];
    const double ux = u.x, uy = u.y;
    const double r = radius_at(u);
    const int n = static_cast<int>(std::ceil((r + 1.5 + kBeyond + 1) / kStep)) + 1;
    if (n > kMostSamples) return std::nullopt;
    Ray& ray = rays[measured];
    float* s = ray.s;
    // The ray stays inside the window when both its ends do; samples stepped in float, as
    // this loop is most of the fit's cost.
    const double end_x = start.x + (n - 1) * kStep * ux, end_y = start.y + (n - 1) * kStep * uy;
    if (std::min(start.x, end_x) < 0 || std::min(start.y, end_y) < 0 ||
        std::max(start.x, end_x) > c.cols - 1 || std::max(start.y, end_y) > c.rows - 1)
      continue;
    {
      const auto* data = c.ptr<float>(0);
      const size_t stride = c.step1();
      auto x = static_cast<float>(start.x), y = static_cast<float>(start.y);
      const auto dx = static_cast<float>(kStep * ux), dy = static_cast<float>(kStep * uy);
      for (int i = 0; i < n; ++i, x += dx, y += dy) {
        const int x0 = std::min(static_cast<int>(x), c.cols - 2),
                  y0 = std::min(static_cast<int>(y), c.rows - 2);
        const float fx = x - static_cast<float>(x0), fy = y - static_cast<float>(y0);
        const float* r0 = data + static_cast<size_t>(y0) * stride + x0;
        const float* r1 = r0 + stride;
        const float top = r0[0] + fx * (r0[1] - r0[0]);
        const float bottom = r1[0] + fx * (r1[1] - r1[0]);
        s[i] = top + fy * (bottom - top);
      }
    }
    // The edge: the steepest fall within reach of the expected radius.
    const int lo = std::max(1, static_cast<int>(0.5 * r / kStep)),
              hi = std::min(n - 2, static_cast<int>((r + 1.5) / kStep));
    int edge = -1;
    float steepest = 0;
    for (int i = lo; i <= hi; ++i)
      if (s[i - 1] - s[i + 1] > steepest) steepest = s[i - 1] - s[i + 1], edge = i;
    if (edge < 0) continue;
    // Outside: the lightest point a little past the edge, so a thin gap of skin between the
    // dot and a darker feature beyond it (the lid between a dot and the slit) counts as skin.
    const int out0 = edge + static_cast<int>(1.0 / kStep),
              out1 = edge + static_cast<int>(kOutside / kStep) + 1;
    if (out1 >= n) continue;
    float outside = s[out0];
    for (int i = out0 + 1; i <= out1; ++i) outside = std::min(outside, s[i]);
    float beyond = outside;  // the darkest a little further out
    for (int i = out1 + 1; i <= std::min(n - 1, edge + static_cast<int>(kBeyond / kStep)); ++i)
      beyond = std::max(beyond, s[i]);
    const int in1 = std::max(0, edge - static_cast<int>(1.5 / kStep)), in0 = std::max(0, in1 - 2);
    float ink = 0;
    for (int i = in0; i <= in1; ++i) ink += s[i];
    ink /= static_cast<float>(in1 - in0 + 1);
    if (ink - outside < least_step) continue;  // no step: the pupil, or noise
    ray.angle = angle, ray.u = u, ray.ink = ink, ray.outside = outside, ray.beyond = beyond;
    ray.edge = edge, ray.n = n;
    ++measured;
  }
  if (measured < kRays / 3) return std::nullopt;
  // Skin: the outside levels most rays see, as a plane (the lid's shading) fitted to them
  // with darker outliers left out. A ray whose outside stays darker than that ran into a
  // darker feature touching the dot (the eye slit, the iris, the lips' gap): its step is a
  // junction of ink, a thin gap and the feature, and its crossing falls short of the edge.
  thread_local std::vector<uint8_t> skin_ray;
  thread_local std::vector<float> levels;
  levels.clear();
  for (size_t k = 0; k < measured; ++k) levels.push_back(rays[k].outside);
  // Start level, flat: a lighter quartile, as the darker features are what is left out.
  auto quartile = levels.begin() + static_cast<long>(levels.size() / 4);
  std::nth_element(levels.begin(), quartile, levels.end());
  cv::Vec3d plane(0, 0, *quartile);  // skin = plane . (cos, sin, 1) of the ray's angle
  skin_ray.assign(measured, 0);
  auto skin_at = [&](cv::Point2d u) { return plane.dot(cv::Vec3d(u.x, u.y, 1)); };
  for (int round = 0; round < 3; ++round) {
    // The plane from the rays that read skin closely.
    size_t chosen = 0;
    for (size_t k = 0; k < measured; ++k) {
      const double skin = skin_at(rays[k].u);
      skin_ray[k] = std::abs(rays[k].outside - skin) <= kPlaneTolerance * (rays[k].ink - skin);
      chosen += skin_ray[k];
    }
    if (chosen < 6) break;
    double ata[3][3] = {}, atb[3] = {}, fitted[3];
    for (size_t k = 0; k < measured; ++k) {
      if (!skin_ray[k]) continue;
      const double row[3] = {rays[k].u.x, rays[k].u.y, 1};
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) ata[i][j] += row[i] * row[j];
        atb[i] += row[i] * static_cast<double>(rays[k].outside);
      }
    }
    if (!solve_normal(ata, atb, fitted)) break;
    plane = cv::Vec3d(fitted[0], fitted[1], fitted[2]);
  }
  // Skin rays for the edge: those not far darker than the plane.
  for (size_t k = 0; k < measured; ++k) {
    const double skin = skin_at(rays[k].u);
    skin_ray[k] = rays[k].outside - skin <= kDarkerOutside * (rays[k].ink - skin);
  }
  for (size_t k = 0; k < measured; ++k) {
    const Ray& ray = rays[k];
    const double angle = ray.angle, ux = ray.u.x, uy = ray.u.y;
    float outside = ray.outside;
    if (skin_ray[k]) {
      // Skin outside: the plane's level, not the ray's own reading. A gap of skin a pixel or
      // two wide between the dot and a darker feature never rises to skin under the blur, and
      // a level read there would put the crossing short of the edge.
      outside = static_cast<float>(plane.dot(cv::Vec3d(ux, uy, 1)));
    } else {
      // A darker feature outside: its own level is the step's far side when it lies flat
      // against the dot (the iris around a lower-lid dot); one that darkens further out is a
      // thin gap before the feature, or a junction of the two, with no clean step: dropped.
      // A small step (a feature nearly as dark as the ink) is dropped too: the least sliver
      // of skin between them, blurred, moves its crossing by most of a pixel.
      const float step = ray.ink - ray.outside;
      const auto skin = static_cast<float>(plane.dot(cv::Vec3d(ux, uy, 1)));
      if (step < kLeastStepShare * (ray.ink - skin)) continue;
      if (ray.beyond - ray.outside > std::max(kFlatShare * step, kFlatFloor * ray.ink)) continue;
    }
    const float ink = ray.ink;
    const float* s = ray.s;
    const int edge = ray.edge, n = ray.n;
    const float half = (ink + outside) / 2;
    // The crossing of the half level nearest the steepest point.
    double t = -1;
    for (int d = 0; d <= 3 && t < 0; ++d)
      for (int i : {edge - d, edge + d - 1}) {
        if (i < 0 || i + 1 >= n || t >= 0) continue;
        if (s[i] >= half && s[i + 1] < half)
          t = (static_cast<double>(i) + (s[i] - half) / (s[i] - s[i + 1])) * kStep;
      }
    if (t <= 0) continue;
    points.emplace_back(start.x + t * ux, start.y + t * uy);
    angles.push_back(angle);
    radius_sum += t;
  }
  if (points.size() < kRays / 3) return std::nullopt;
  // The rim left must surround the dot: a gap of more than half a turn leaves the centre free
  // to slide along it.
  double gap = 0;
  for (size_t i = 0; i < angles.size(); ++i) {
    const double next = i + 1 < angles.size() ? angles[i + 1] : angles[0] + 2 * kPi;
    gap = std::max(gap, next - angles[i]);
  }
  if (gap > kPi) return std::nullopt;
  const double scale = radius_sum / static_cast<double>(points.size());
  cv::Matx<double, 5, 1> conic;
  auto centre = fit_ellipse_centre(points, start, scale, conic);
  if (!centre) return std::nullopt;
  // One round against outliers (a ray that found the iris's edge instead of the dot's).
  thread_local std::vector<double> residuals;
  residuals.clear();
  for (const cv::Point2d& p : points) residuals.push_back(conic_distance(conic, p, start, scale));
  thread_local std::vector<double> sorted;
  sorted = residuals;
  auto mid = sorted.begin() + static_cast<long>(sorted.size() / 2);
  std::nth_element(sorted.begin(), mid, sorted.end());
  const double limit = std::max(0.25, 3 * *mid);
  size_t kept = 0;
  for (size_t i = 0; i < points.size(); ++i)
    if (residuals[i] <= limit) points[kept++] = points[i];
  if (kept < points.size()) {
    points.resize(kept);
    if (points.size() < kRays / 3) return std::nullopt;
    centre = fit_ellipse_centre(points, start, scale, conic);
    if (!centre) return std::nullopt;
  }
  return centre;
}

}  // namespace

namespace {

// The contrast map (and its 3x3 mean) of the window that holds every dot centred within
// `radius` of `guess`; buffers kept per thread, as this runs per dot per frame.
struct ContrastWindow {
  cv::Rect rect;
  cv::Point2d guess;  // in window pixels
  const cv::Mat* c = nullptr;
  const cv::Mat* smooth = nullptr;
};

bool contrast_window(const cv::Mat& gray, cv::Point2d guess, double radius,
                     const DotOptions& options, ContrastWindow& out) {
  CV_Assert(gray.type() == CV_8UC1);
  const double max_r = options.max_diameter_px / 2;
  const int half = static_cast<int>(std::ceil(radius + max_r + 2));
  const cv::Rect image_rect(0, 0, gray.cols, gray.rows);
  out.rect = cv::Rect(static_cast<int>(std::lround(guess.x)) - half,
                      static_cast<int>(std::lround(guess.y)) - half, 2 * half + 1, 2 * half + 1) &
             image_rect;
  if (out.rect.width < 5 || out.rect.height < 5) return false;
  const cv::Mat patch = gray(out.rect);
  const float background = border_median(patch);
  thread_local cv::Mat c, smooth;
  c.create(patch.size(), CV_32F);
  for (int y = 0; y < patch.rows; ++y) {
    const uint8_t* in = patch.ptr<uint8_t>(y);
    float* row = c.ptr<float>(y);
    // (contrast_of with the polarity chosen outside the loop, which then vectorises)
    if (options.polarity == DotPolarity::Dark)
      for (int x = 0; x < patch.cols; ++x) row[x] = background - static_cast<float>(in[x]);
    else
      for (int x = 0; x < patch.cols; ++x) row[x] = static_cast<float>(in[x]) - background;
  }
  out.guess = {guess.x - out.rect.x, guess.y - out.rect.y};
  // The smoothed contrast is read only within radius + 1 of the guess (the core's search and
  // its neighbours' test), a tenth of the window: cv::blur's values there, computed there only.
  smooth.create(patch.size(), CV_32F);
  const int reach = static_cast<int>(std::ceil(radius)) + 2;
  const int gx = static_cast<int>(std::floor(out.guess.x)),
            gy = static_cast<int>(std::floor(out.guess.y));
  box3_mean(c, smooth, {gx - reach, gy - reach, 2 * reach + 2, 2 * reach + 2});
  out.c = &c;
  out.smooth = &smooth;
  return true;
}

std::optional<Dot> measure_peak(const cv::Mat& c, cv::Point peak, float peak_value,
                                const cv::Rect& window, const DotOptions& options);

}  // namespace

std::optional<Dot> refine_dot(const cv::Mat& gray, cv::Point2d guess, double radius,
                              const DotOptions& options) {
  ContrastWindow w;
  if (!contrast_window(gray, guess, radius, options, w)) return std::nullopt;
  const cv::Mat& smooth = *w.smooth;
  // The strongest point within `radius` of the guess is the dot's core.
  const cv::Point2d g = w.guess;
  cv::Point peak(-1, -1);
  float peak_value = -1e9f;
  const int py0 = std::max(0, static_cast<int>(std::floor(g.y - radius))),
            py1 = std::min(smooth.rows - 1, static_cast<int>(std::ceil(g.y + radius))),
            px0 = std::max(0, static_cast<int>(std::floor(g.x - radius))),
            px1 = std::min(smooth.cols - 1, static_cast<int>(std::ceil(g.x + radius)));
  for (int y = py0; y <= py1; ++y)
    for (int x = px0; x <= px1; ++x) {
      const double dx = x - g.x, dy = y - g.y;
      if (dx * dx + dy * dy > radius * radius) continue;
      if (smooth.at<float>(y, x) > peak_value) peak_value = smooth.at<float>(y, x), peak = {x, y};
    }
  if (peak.x < 0 || peak_value < options.min_contrast) return std::nullopt;
  return measure_peak(*w.c, peak, peak_value, w.rect, options);
}

std::vector<Dot> dots_near(const cv::Mat& gray, cv::Point2d guess, double radius,
                           const DotOptions& options, int most, double least_contrast) {
  ContrastWindow w;
  if (!contrast_window(gray, guess, radius, options, w)) return {};
  const cv::Mat& smooth = *w.smooth;
  struct Peak {
    double distance;
    cv::Point at;
    float value;
  };
  std::vector<Peak> peaks;
  const cv::Point2d g = w.guess;
  const int py0 = std::max(1, static_cast<int>(std::floor(g.y - radius))),
            py1 = std::min(smooth.rows - 2, static_cast<int>(std::ceil(g.y + radius))),
            px0 = std::max(1, static_cast<int>(std::floor(g.x - radius))),
            px1 = std::min(smooth.cols - 2, static_cast<int>(std::ceil(g.x + radius)));
  for (int y = py0; y <= py1; ++y)
    for (int x = px0; x <= px1; ++x) {
      const double dx = x - g.x, dy = y - g.y;
      if (dx * dx + dy * dy > radius * radius) continue;
      const float v = smooth.at<float>(y, x);
      if (v < options.min_contrast || v < least_contrast) continue;
      bool top = true;
      for (int yy = -1; yy <= 1 && top; ++yy)
        for (int xx = -1; xx <= 1; ++xx)
          if ((xx || yy) && smooth.at<float>(y + yy, x + xx) > v) top = false;
      if (top) peaks.push_back({std::sqrt(dx * dx + dy * dy), {x, y}, v});
    }
  std::sort(peaks.begin(), peaks.end(),
            [](const Peak& a, const Peak& b) { return a.distance < b.distance; });
  std::vector<Dot> out;
  int tried = 0;  // noise on skin has many weak maxima: only the nearest few are measured
  for (const Peak& p : peaks) {
    if (static_cast<int>(out.size()) >= most || tried++ >= 2 * most) break;
    auto d = measure_peak(*w.c, p.at, p.value, w.rect, options);
    if (!d) continue;
    bool seen = false;  // a plateau's several maxima measure as one dot
    for (const Dot& o : out)
      if (cv::norm(o.center - d->center) < 1.0) seen = true;
    if (!seen) out.push_back(*d);
  }
  return out;
}

namespace {

// The centre m about which the dot's contrast `c` best overlaps its own point reflection
// (DotOptions::symmetric_centre): the largest S(m), the sum over the pixels p within `radius` of
// m of min(w(p), w(2m - p)), w the contrast above `floor` and at most `top` on the dot's own
// pixels (`own_at`: its blob and rim, as for the centroid) and 0 elsewhere. A dot is symmetric
// about its centre, where S is its whole weight; a feature touching it from one side reflects
// onto what lies opposite (skin) and adds next to nothing. (Without the blob, a long line,
// symmetric about any point on it, drew m out along it: a small dot seen edge-on under a head
// turn went 2.4 px into the eye.) On the half-pixel grid 2m - p is a pixel, so S is read
// without interpolation; m is hill-climbed there from `start`, then placed between grid points
// (below). nullopt when the peak lies more than `reach` pixels from `start`.
template <typename Own>
std::optional<cv::Point2d> symmetric_centre(const cv::Mat& c, cv::Point2d start, double radius,
                                            float floor, float top, double reach, Own own_at) {
  const double r2 = radius * radius;
  // The weights of every pixel the search can read, once: a square about the start reaching
  // the disc's radius past the farthest centre tried (zero outside the image and the dot).
  const int cx = static_cast<int>(std::lround(start.x)),
            cy = static_cast<int>(std::lround(start.y));
  const int half = static_cast<int>(std::ceil(radius + reach)) + 3, width = 2 * half + 1;
  thread_local std::vector<float> weights;
  weights.assign(static_cast<size_t>(width * width), 0.0f);
  for (int y = std::max(0, cy - half); y <= std::min(c.rows - 1, cy + half); ++y) {
    const float* row = c.ptr<float>(y);
    for (int x = std::max(0, cx - half); x <= std::min(c.cols - 1, cx + half); ++x)
      if (own_at(x, y))
        weights[static_cast<size_t>((y - cy + half) * width + (x - cx + half))] =
            std::clamp(row[x] - floor, 0.0f, top - floor);
  }
  auto weight = [&](int x, int y) {
    const int u = x - cx + half, v = y - cy + half;
    if (u < 0 || v < 0 || u >= width || v >= width) return 0.0f;
    return weights[static_cast<size_t>(v * width + u)];
  };
  // S at m = (i / 2, j / 2).
  auto overlap = [&](int i, int j) {
    const double mx = 0.5 * i, my = 0.5 * j;
    double sum = 0;
    for (int y = static_cast<int>(std::ceil(my - radius)); y <= static_cast<int>(my + radius); ++y)
      for (int x = static_cast<int>(std::ceil(mx - radius)); x <= static_cast<int>(mx + radius);
           ++x) {
        const double dx = x - mx, dy = y - my;
        if (dx * dx + dy * dy <= r2) sum += std::min(weight(x, y), weight(i - x, j - y));
      }
    return sum;
  };
  const int i0 = static_cast<int>(std::lround(2 * start.x)),
            j0 = static_cast<int>(std::lround(2 * start.y));
  const int most = static_cast<int>(std::ceil(2 * reach));
  // S on a small square of grid points about the start, filled as the climb reaches them.
  const int side = 2 * most + 5;
  thread_local std::vector<double> grid;
  grid.assign(static_cast<size_t>(side * side), -1);
  auto at = [&](int i, int j) {
    double& v = grid[static_cast<size_t>((j - j0 + most + 2) * side + (i - i0 + most + 2))];
    if (v < 0) v = overlap(i, j);
    return v;
  };
  int bi = i0, bj = j0;
  for (int step = 0; step <= 2 * most; ++step) {
    int ni = bi, nj = bj;
    double best = at(bi, bj);
    for (int dj = -1; dj <= 1; ++dj)
      for (int di = -1; di <= 1; ++di)
        if ((di || dj) && at(bi + di, bj + dj) > best)
          best = at(bi + di, bj + dj), ni = bi + di, nj = bj + dj;
    if (ni == bi && nj == bj) break;
    if (std::abs(ni - i0) > most || std::abs(nj - j0) > most) return std::nullopt;
    bi = ni, bj = nj;
  }
  // Between grid points, each axis alone: where the line through the two samples left of the
  // peak meets the line through the two right of it. Their slopes differ where a feature lies
  // on one side (the line's rows gain as m moves toward it while the rest lose), and a V of
  // equal slopes through the peak and its neighbours would lean toward the feature.
  auto vertex = [](double m2, double m1, double p1, double p2) {
    const double left = m1 - m2, right = p1 - p2;  // rise toward the peak on each side
    if (!(left > 0) || !(right > 0)) return 0.0;
    return 0.5 * std::clamp((p1 - m1 + right - left) / (left + right), -0.5, 0.5);
  };
  return cv::Point2d(
      0.5 * bi + vertex(at(bi - 2, bj), at(bi - 1, bj), at(bi + 1, bj), at(bi + 2, bj)),
      0.5 * bj + vertex(at(bi, bj - 2), at(bi, bj - 1), at(bi, bj + 1), at(bi, bj + 2)));
}

std::optional<Dot> measure_peak(const cv::Mat& c, cv::Point peak, float peak_value,
                                const cv::Rect& window, const DotOptions& options) {
  // The peak's value is a 3x3 mean of the contrast; the blobs below grow from the strongest
  // pixel of that box. In sensor noise a faint dot's own pixel at the peak can lie below 0.9
  // of the mean (the core's level, 2 grey levels under a contrast of 20), which left the dot
  // with no core at all; some pixel of the box is at least the mean.
  peak = strongest_around(c, peak);
  // Its extent: the pixels connected to the peak above a share of the peak. Half is the
  // dot's true edge on plain skin. A dot that touches a darker feature (an eyebrow, the
  // iris, a nostril, the shadow under the chin) merges with it at half; those features are
  // lighter than the dot's core, so at a higher share the dot stands alone. A lone dot's
  // edge is steep: its size hardly changes with the share, where a merged blob's jumps.
  // The lowest share whose blob is no wider than the core's plus its rim is the dot.
  const Extent core = extent_at(c, peak, static_cast<float>(kExtentLevels[4] * peak_value));
  if (core.area <= 0 || core.touches_edge) return std::nullopt;
  const double rim = std::max(1.5, 0.2 * core.diameter);
  const double widest = core.diameter + rim;
  const auto most_pixels = static_cast<size_t>(kPi / 4 * widest * widest) + 1;
  auto extent_of = [&](int level) {
    return level == 4 ? core
                      : extent_at(c, peak, static_cast<float>(kExtentLevels[level] * peak_value),
                                  most_pixels);
  };
  auto fits = [&](const Extent& e) { return !e.touches_edge && e.diameter <= widest; };
  // A lower share's blob holds a higher share's, so passing is monotonic in the share: half
  // first (a dot on plain skin), else the lowest passing share by bisection (the core
  // always passes).
  Extent extent = extent_of(0);
  int chosen = 0;
  if (!fits(extent)) {
    int lo = 1, hi = 4;
    Extent at_hi = core;
    while (lo < hi) {
      const int mid = (lo + hi) / 2;
      Extent e = extent_of(mid);
      if (fits(e))
        hi = mid, at_hi = std::move(e);
      else
        lo = mid + 1;
    }
    chosen = hi;
    extent = std::move(at_hi);
  }
  // (DotOptions::raise_share_for_roundness.)
  auto round_enough = [&](const Extent& e, int level) {
    return e.roundness >= (level > 0 ? options.min_roundness_merged : options.min_roundness);
  };
  while (options.raise_share_for_roundness && chosen < 4 && !round_enough(extent, chosen))
    extent = extent_of(++chosen);
  const double share = kExtentLevels[chosen];
  // Above half the blob is smaller than the dot: its rim (the anti-aliased edge, about a
  // pixel wide) is added back so the reported size does not depend on the share.
  const double diameter = share > kExtentLevels[0]
                              ? extent.diameter + (share - kExtentLevels[0]) * 2.5
                              : extent.diameter;
  // A dot cut off from a darker feature at a high share of its peak is a small blob with a
  // ragged edge (the lower-lid dot against the iris, more so in noise): less round than a
  // whole dot measured at half.
  const double least_roundness =
      share > kExtentLevels[0] ? options.min_roundness_merged : options.min_roundness;
  if (diameter < options.min_diameter_px || diameter > options.max_diameter_px ||
      extent.roundness < least_roundness || extent.elongation > options.max_elongation)
    return std::nullopt;
  cv::Point2d centre = extent.centre;

  // Contrast-weighted centroid over a disc just wider than the dot, re-centred twice. The
  // small floor keeps background texture inside the disc from pulling the centre.
  const float floor = 0.15f * peak_value;
  const double disc = diameter / 2 + 2.0;
  // Only the dot's own blob and its rim (one pixel around it) count: a darker feature's
  // pixels inside the disc (the iris beside a lid dot, the lips beside a lip dot, even when
  // they do not merge with the dot at half its contrast) would pull the centre toward it,
  // by about half a pixel on the rendered head.
  // (The blob grown by a 3x3 cross, as cv::dilate would, read only where the disc needs it.)
  const cv::Mat& blob = extent.region;
  auto own_at = [&blob](int x, int y) {
    const uint8_t* row = blob.ptr<uint8_t>(y);
    return row[x] || (x > 0 && row[x - 1]) || (x + 1 < blob.cols && row[x + 1]) ||
           (y > 0 && blob.ptr<uint8_t>(y - 1)[x]) ||
           (y + 1 < blob.rows && blob.ptr<uint8_t>(y + 1)[x]);
  };
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
        if (!own_at(x, y)) continue;
        const double w = std::clamp(row[x] - floor, 0.0f, peak_value - floor);
        sw += w, sx += w * x, sy += w * y;
      }
    }
    if (sw <= 0) return std::nullopt;
    centre = {sx / sw, sy / sw};
  }
  if (options.symmetric_centre) {
    // From the centroid, which a feature on one side pulls by well under the dot's radius; over
    // the dot's own pixels as the centroid, on a disc a little wider (it only bounds the sum).
    if (auto m = symmetric_centre(c, centre, disc + 0.5, floor, peak_value,
                                  std::max(1.0, diameter / 4), own_at))
      centre = *m;
  }
  // What lies just outside the dot: a dot on skin is ringed by skin, the pupil by the iris
  // (dark), so the ring's median contrast tells a pupil from a dot of the same size.
  thread_local std::vector<float> ring;
  ring.clear();
  const double inner = diameter / 2 + 1.5, outer = diameter / 2 + 3.5;
  for (int y = std::max(0, static_cast<int>(centre.y - outer));
       y <= std::min(c.rows - 1, static_cast<int>(centre.y + outer + 1)); ++y) {
    const float* row = c.ptr<float>(y);
    for (int x = std::max(0, static_cast<int>(centre.x - outer));
         x <= std::min(c.cols - 1, static_cast<int>(centre.x + outer + 1)); ++x) {
      const double dx = x - centre.x, dy = y - centre.y, r2 = dx * dx + dy * dy;
      if (r2 >= inner * inner && r2 <= outer * outer) ring.push_back(row[x]);
    }
  }
  double surround = 0, spread = 0;
  if (!ring.empty()) {
    auto mid = ring.begin() + static_cast<long>(ring.size() / 2);
    std::nth_element(ring.begin(), mid, ring.end());
    surround = std::max(0.0, static_cast<double>(*mid) / peak_value);
  }
  if (surround > options.max_surround) return std::nullopt;
  // How uneven the surroundings are, for the edge fit only: the 10th to the 90th percentile.
  if (options.edge_fit && !ring.empty()) {
    auto mid = ring.begin() + static_cast<long>(ring.size() / 2);
    auto low = ring.begin() + static_cast<long>(ring.size() / 10);
    std::nth_element(ring.begin(), low, mid);
    auto high = ring.begin() + static_cast<long>(ring.size() * 9 / 10);
    std::nth_element(mid, high, ring.end());
    spread = static_cast<double>(*high - *low);
  }
  // The centroid starts the edge fit, which is not pulled by what lies beside the dot; it
  // stands where the rim is too broken to fit (a dot half hidden, or merged all round), and
  // on even surroundings (a dot on the cheek), where it has no pull to undo: the fit costs
  // about as much as the rest of the measurement.
  if (options.edge_fit && spread > kEvenRing * peak_value) {
    // The blob's ellipse, grown by the rim a share above half cuts off.
    const double grow = (share - kExtentLevels[0]) * 1.25;
    const double ra = extent.semi_long + grow, rb = extent.semi_short + grow;
    const double ce = std::cos(extent.angle), se = std::sin(extent.angle);
    auto radius_at = [&](cv::Point2d u) {  // along u, from the centre
      return ra * rb / std::hypot(rb * (u.x * ce + u.y * se), ra * (u.y * ce - u.x * se));
    };
    const double least_step =
        std::max(options.min_contrast / 2, 0.1 * static_cast<double>(peak_value));
    // Twice, unless the first fit hardly moved: rays cast from near the true centre meet the
    // rim square on. A fit that lands far from the centroid rests on a broken rim and is not
    // trusted.
    cv::Point2d start = centre;
    for (int pass = 0; pass < 2; ++pass) {
      auto fitted = edge_ellipse_centre(c, start, radius_at, least_step);
      if (!fitted || cv::norm(*fitted - centre) > 0.1 * diameter + 0.25) break;
      const double moved = cv::norm(*fitted - start);
      start = *fitted;
      if (pass == 1 || moved < kSettled) {
        centre = start;
        break;
      }
    }
  }
  return Dot{{centre.x + window.x, centre.y + window.y},
             diameter,
             peak_value,
             surround,
             extent.elongation,
             share,
             extent.roundness};
}

}  // namespace

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

void DotOptions::validate() const {
  OptionCheck("DotOptions")
      .positive("min_diameter_px", min_diameter_px)
      .at_least("max_diameter_px", max_diameter_px, min_diameter_px)
      .not_negative("min_contrast", min_contrast)
      .within("min_roundness", min_roundness, 0, 1)
      .within("min_roundness_merged", min_roundness_merged, 0, 1)
      .at_least("max_elongation", max_elongation, 1)
      .positive("max_surround", max_surround);
}

}  // namespace rostro::tracking
