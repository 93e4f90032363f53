#include "tracking/tag_alignment.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/core/hal/intrin.hpp>
#include <opencv2/imgproc.hpp>

namespace rostro::tracking {
namespace {

// The pattern is sampled half a cell past the black square: the paper's edge lies further out
// on a printed tag, but a tag drawn on skin or cut at its border has no more paper than that.
constexpr double kPaperCells = 0.5;
constexpr double kHalfReadCellPx = 6;  // cells at least this wide are read at half the samples
constexpr int kMaxIterations = 20;
constexpr double kSettledPx = 0.01;  // a step that moves no corner further ends the alignment
// The image must look like the pattern where it was aligned: at most this share of the samples
// off by more than kFarOff of the ink-to-paper contrast. Blur and noise leave small residuals
// along every edge; something over the tag (a hand, hair) leaves large ones where it is.
constexpr double kFarOff = 0.35;
constexpr double kMostFarOff = 0.03;
constexpr double kLeastContrast = 20;  // grey levels from ink to paper
constexpr int kBlurTerm = 3;           // the Laplacian's place in the lighting row

// The pattern's corners in its own coordinates, in libapriltag's order: bottom-left,
// bottom-right, top-right, top-left of the upright tag (image y down).
const std::array<cv::Point2d, 4> kPatternCorners = {cv::Point2d(-1, 1), cv::Point2d(1, 1),
                                                    cv::Point2d(1, -1), cv::Point2d(-1, -1)};

cv::Matx33d homography_between(const std::array<cv::Point2d, 4>& from,
                               const std::array<cv::Point2d, 4>& to) {
  std::vector<cv::Point2f> a, b;
  for (int k = 0; k < 4; ++k) a.emplace_back(from[k]), b.emplace_back(to[k]);
  return cv::Matx33d(cv::getPerspectiveTransform(a, b));
}

cv::Point2d apply(const cv::Matx33d& h, cv::Point2d p) {
  const double w = h(2, 0) * p.x + h(2, 1) * p.y + h(2, 2);
  return {(h(0, 0) * p.x + h(0, 1) * p.y + h(0, 2)) / w,
          (h(1, 0) * p.x + h(1, 1) * p.y + h(1, 2)) / w};
}

}  // namespace

// The lighting's regressors at a sample: seen = (gain + gain_x x + gain_y y) * pattern
// + blur * laplacian + offset + offset_x x + offset_y y. The light falls off across a tag on a
// curved headband or a turned face, darkening ink and paper alike (the gain's slope) and
// adding its own glow (the offset's). Padded to eight lanes with a 0.
void TagPattern::Sample::set_lighting(float value, float laplacian) {
  const float row[kLightingLanes] = {value, value * x, value * y, laplacian, 1.0f, x, y, 0.0f};
  std::copy(std::begin(row), std::end(row), light);
}

TagPattern::TagPattern(const cv::Mat& bits, int black_width, double cell_px, double softness_px)
    : cell_px_(cell_px), softness_px_(softness_px) {
  CV_Assert(bits.type() == CV_8UC1 && bits.rows == bits.cols && black_width > 0);
  const int border = (bits.cols - black_width) / 2;  // white cells around the black square
  // About one sample per image pixel: the alignment then reads each edge pixel once.
  const double step = 1.0 / std::clamp(cell_px, 2.0, 16.0);  // cells
  const int pad = 3;  // samples beyond the used ones, for the softening
  const int used = static_cast<int>(std::lround((black_width + 2 * kPaperCells) / step));
  const int side = used + 2 * pad;
  const double origin = -kPaperCells - pad * step;  // cells from the black square's corner

  // Each sample's share of paper, exactly: its square meets at most two cells along each axis.
  auto paper = [&](int row, int col) {  // bit cell from the black square's corner
    row += border, col += border;
    if (col < 0 || row < 0 || col >= bits.cols || row >= bits.rows) return 1.0;
    return bits.at<uint8_t>(row, col) > 127 ? 1.0 : 0.0;
  };
  struct Overlap {
    int cell[2];
    double share[2];
  };
  auto overlap = [&](int i) {  // sample i's extent along one axis, split at the cell edge
    const double lo = origin + i * step, hi = lo + step;
    const int first = static_cast<int>(std::floor(lo));
    const double cut = std::min(hi, first + 1.0);
    return Overlap{{first, first + 1}, {(cut - lo) / step, (hi - cut) / step}};
  };
  cv::Mat1f pattern(side, side);
  for (int r = 0; r < side; ++r) {
    const Overlap y = overlap(r);
    for (int c = 0; c < side; ++c) {
      const Overlap x = overlap(c);
      double share = 0;
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b) share += y.share[a] * x.share[b] * paper(y.cell[a], x.cell[b]);
      pattern(r, c) = static_cast<float>(share);
    }
  }
  // A sample spans 1 / (step * cell_px) image pixels: the softness in samples.
  px_per_sample_ = step * cell_px;
  cv::GaussianBlur(pattern, pattern, {0, 0}, std::max(0.1, softness_px / px_per_sample_));

  // Pattern coordinates: the black square spans [-1, 1]; a sample is `scale` of them.
  const double half = black_width / 2.0;
  const double scale = step / half;
  cv::Mat1f gx(side, side, 0.0f), gy(side, side, 0.0f), strength(side, side, 0.0f);
  // In samples: blurring the pattern by a further sigma adds sigma^2 / 2 of it, to first order.
  cv::Mat1f laplacian;
  cv::Laplacian(pattern, laplacian, CV_32F);
  for (int r = 1; r + 1 < side; ++r)
    for (int c = 1; c + 1 < side; ++c) {
      gx(r, c) = static_cast<float>((pattern(r, c + 1) - pattern(r, c - 1)) / (2 * scale));
      gy(r, c) = static_cast<float>((pattern(r + 1, c) - pattern(r - 1, c)) / (2 * scale));
      strength(r, c) = std::abs(pattern(r, c + 1) - pattern(r, c - 1)) +
                       std::abs(pattern(r + 1, c) - pattern(r - 1, c));
    }
  // Only the samples on or next to an edge: elsewhere the pattern is flat and tells nothing of
  // the corners (the ink and paper levels come from the edges' two sides as well).
  cv::Mat1f near_edge;
  cv::dilate(strength, near_edge, cv::Mat());
  cv::Matx<double, 8, 8> hessian = cv::Matx<double, 8, 8>::zeros();
  // A large tag is read at half its samples, in a checkerboard: every row and column along an
  // edge keeps samples, and there are still several hundred.
  const bool every_other = cell_px >= kHalfReadCellPx;
  for (int r = pad; r < pad + used; ++r)
    for (int c = pad; c < pad + used; ++c) {
      if (near_edge(r, c) < 0.02f || (every_other && (r + c) % 2)) continue;
      Sample s;
      const double u = origin + (c + 0.5) * step, v = origin + (r + 0.5) * step;
      const double x = (u - half) / half, y = (v - half) / half;
      s.x = static_cast<float>(x), s.y = static_cast<float>(y);
      const double dx = gx(r, c), dy = gy(r, c);
      // d(warp)/dp at identity for H = [[1+p0, p1, p2], [p3, 1+p4, p5], [p6, p7, 1]].
      const double sd[8] = {
          dx * x, dx * y, dx, dy * x, dy * y, dy, -x * (dx * x + dy * y), -y * (dx * x + dy * y)};
      for (int i = 0; i < 8; ++i) {
        s.sd[i] = static_cast<float>(sd[i]);
        for (int j = 0; j < 8; ++j) hessian(i, j) += sd[i] * sd[j];
      }
      s.set_lighting(pattern(r, c), laplacian(r, c));
      samples_.push_back(s);
    }
  hessian_inverse_ = hessian.inv(cv::DECOMP_CHOLESKY);
  cv::Matx<double, kLighting, kLighting> lighting = cv::Matx<double, kLighting, kLighting>::zeros();
  sd_light_ = cv::Matx<double, 8, kLighting>::zeros();
  for (const Sample& s : samples_)
    for (int i = 0; i < kLighting; ++i) {
      for (int j = 0; j < kLighting; ++j) lighting(i, j) += double(s.light[i]) * s.light[j];
      for (int j = 0; j < 8; ++j) sd_light_(j, i) += double(s.sd[j]) * s.light[i];
    }
  lighting_inverse_ = lighting.inv(cv::DECOMP_SVD);
}

std::optional<TagAlignment> TagPattern::align(const cv::Mat& gray,
                                              const std::array<cv::Point2d, 4>& corners) const {
  CV_Assert(gray.type() == CV_8UC1);
  if (samples_.empty()) return std::nullopt;
  cv::Matx33d h = homography_between(kPatternCorners, corners);
  thread_local std::vector<float> seen;  // per tag per frame: no allocation once grown
  seen.resize(samples_.size());
  auto corners_of = [](const cv::Matx33d& m) {
    std::array<cv::Point2d, 4> out;
    for (int k = 0; k < 4; ++k) out[k] = apply(m, kPatternCorners[k]);
    return out;
  };
  std::array<cv::Point2d, 4> now = corners;
  double gain = 0, blur = 0;
  cv::Vec<double, kLighting> lighting;
  bool settled = false;
  for (int iteration = 0; iteration < kMaxIterations && !settled; ++iteration) {
    // The image under each sample, bilinear, and its sums against the lighting's regressors.
    const float h00 = static_cast<float>(h(0, 0)), h01 = static_cast<float>(h(0, 1)),
                h02 = static_cast<float>(h(0, 2)), h10 = static_cast<float>(h(1, 0)),
                h11 = static_cast<float>(h(1, 1)), h12 = static_cast<float>(h(1, 2)),
                h20 = static_cast<float>(h(2, 0)), h21 = static_cast<float>(h(2, 1)),
                h22 = static_cast<float>(h(2, 2));
    const float right = static_cast<float>(gray.cols - 1),
                bottom = static_cast<float>(gray.rows - 1);
    // The image's sums against the lighting's regressors and the steepest-descent rows, in
    // floats, eight lanes at once: a step's precision is the convergence test's, not the sums'
    // last digits.
    cv::v_float32x4 light_lo = cv::v_setzero_f32(), light_hi = light_lo, sd_lo = light_lo,
                    sd_hi = light_lo;
    for (size_t k = 0; k < samples_.size(); ++k) {
      const Sample& s = samples_[k];
      const float w = 1.0f / (h20 * s.x + h21 * s.y + h22);
      const float px = (h00 * s.x + h01 * s.y + h02) * w, py = (h10 * s.x + h11 * s.y + h12) * w;
      if (!(px >= 0 && py >= 0 && px < right && py < bottom)) return std::nullopt;
      const int x0 = static_cast<int>(px), y0 = static_cast<int>(py);
      const float fx = px - static_cast<float>(x0), fy = py - static_cast<float>(y0);
      const uint8_t* r0 = gray.ptr<uint8_t>(y0) + x0;
      const uint8_t* r1 = r0 + gray.step[0];
      const float v =
          (1 - fy) * ((1 - fx) * r0[0] + fx * r0[1]) + fy * ((1 - fx) * r1[0] + fx * r1[1]);
      seen[k] = v;
      const cv::v_float32x4 vv = cv::v_setall_f32(v);
      light_lo = cv::v_fma(cv::v_load(s.light), vv, light_lo);
      light_hi = cv::v_fma(cv::v_load(s.light + 4), vv, light_hi);
      sd_lo = cv::v_fma(cv::v_load(s.sd), vv, sd_lo);
      sd_hi = cv::v_fma(cv::v_load(s.sd + 4), vv, sd_hi);
    }
    float light_sums[kLightingLanes], sd_sums[8];
    cv::v_store(light_sums, light_lo), cv::v_store(light_sums + 4, light_hi);
    cv::v_store(sd_sums, sd_lo), cv::v_store(sd_sums + 4, sd_hi);
    // The lighting and the blur, by least squares (Sample::set_lighting). A symmetric blur
    // moves no edge, but fitted with a pattern of the wrong softness it pulls the corners toward
    // the code's busier side; the blur term absorbs that.
    cv::Vec<double, kLighting> b;
    for (int i = 0; i < kLighting; ++i) b[i] = light_sums[i];
    const cv::Vec<double, kLighting> x = lighting_inverse_ * b;
    gain = x[0];
    if (gain < kLeastContrast) return std::nullopt;
    lighting = x;
    // The steepest descent against the residual seen - model: its model part is the fitted
    // lighting times the pattern's own sums of steepest-descent rows and regressors.
    cv::Vec<double, 8> g;
    for (int i = 0; i < 8; ++i) g[i] = sd_sums[i];
    g -= sd_light_ * x;
    blur = x[kBlurTerm] / gain;
    const cv::Vec<double, 8> dp = hessian_inverse_ * g * (1.0 / gain);
    const cv::Matx33d step(1 + dp[0], dp[1], dp[2], dp[3], 1 + dp[4], dp[5], dp[6], dp[7], 1);
    h = h * step.inv();
    const auto next = corners_of(h);
    double moved = 0;
    for (int k = 0; k < 4; ++k) moved = std::max(moved, cv::norm(next[k] - now[k]));
    now = next;
    settled = moved < kSettledPx;
  }
  if (!settled) return std::nullopt;
  // The residuals of the last step's samples: how much of the tag does not look like it.
  int far = 0;
  const float far_level = static_cast<float>(kFarOff * gain);
  float fitted[kLightingLanes] = {};
  for (int i = 0; i < kLighting; ++i) fitted[i] = static_cast<float>(lighting[i]);
  for (size_t k = 0; k < samples_.size(); ++k) {
    float model = 0;
    for (int i = 0; i < kLightingLanes; ++i) model += fitted[i] * samples_[k].light[i];
    far += std::abs(seen[k] - model) > far_level;
  }
  if (far > kMostFarOff * static_cast<double>(samples_.size())) return std::nullopt;
  // Blurring by sigma adds sigma^2 / 2 of the Laplacian (in samples), to first order.
  const double soft = softness_px_ / px_per_sample_;
  const double image_soft = std::sqrt(std::max(0.0, soft * soft + 2 * blur));
  return TagAlignment{now, image_soft * px_per_sample_};
}

TagAligner::TagAligner(cv::Mat bits, int black_width)
    : bits_(std::move(bits)), black_width_(black_width) {}

std::optional<std::array<cv::Point2d, 4>> TagAligner::align(
    const cv::Mat& gray, const std::array<cv::Point2d, 4>& corners, double max_move_px) {
  double side = 0;
  for (int k = 0; k < 4; ++k) side += cv::norm(corners[k] - corners[(k + 1) % 4]) / 4;
  const double cell_px = side / black_width_;
  auto result = pattern(cell_px, softness_px_).align(gray, corners);
  if (!result) return std::nullopt;
  // A pattern much sharper or softer than the image pulls the corners: again with one as soft
  // as the image seems (the estimate is first order, so a far one is refined once more), and
  // the next frame starts from it.
  for (int pass = 0; pass < 2; ++pass) {
    const double level = std::clamp(std::round(result->blur_px / kSoftnessStep) * kSoftnessStep,
                                    kSoftnessStep, kSoftestPx);
    if (std::abs(level - softness_px_) < kSoftnessStep / 2) break;
    softness_px_ = level;
    result = pattern(cell_px, softness_px_).align(gray, result->corners);
    if (!result) return std::nullopt;
  }
  for (int k = 0; k < 4; ++k)
    if (cv::norm(result->corners[k] - corners[k]) > max_move_px) return std::nullopt;
  return result->corners;
}

const TagPattern& TagAligner::pattern(double cell_px, double softness_px) {
  for (const TagPattern& p : patterns_)
    if (p.softness_px() == softness_px && std::abs(p.cell_px() / cell_px - 1) < kSizeTolerance)
      return p;
  if (patterns_.size() >= kMostPatterns) patterns_.erase(patterns_.begin());
  patterns_.emplace_back(bits_, black_width_, cell_px, softness_px);
  return patterns_.back();
}

}  // namespace rostro::tracking
