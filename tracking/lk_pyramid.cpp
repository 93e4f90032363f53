#include "tracking/lk_pyramid.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/video/tracking.hpp>

namespace rostro::tracking {
namespace {

// Reflect-101 index into [0, n): -1 -> 1, n -> n - 2 (OpenCV's default border).
inline int reflect(int i, int n) {
  if (n == 1) return 0;
  if (i < 0) return -i;
  if (i >= n) return 2 * n - 2 - i;
  return i;
}

// OpenCV's calcScharrDeriv (modules/video/src/lkpyramid.cpp) on the pixels [x0, x1) x
// [y0, y1) of `src`: dx = [3 10 3]^T * [-1 0 1], dy = [-1 0 1]^T * [3 10 3], as shorts.
void scharr_window(const cv::Mat& src, cv::Mat& dst, int x0, int y0, int x1, int y1) {
  const int rows = src.rows, cols = src.cols;
  x0 = std::max(x0, 0), y0 = std::max(y0, 0), x1 = std::min(x1, cols), y1 = std::min(y1, rows);
  if (x0 >= x1 || y0 >= y1) return;
  const int width = x1 - x0 + 2;  // one column either side
  int smooth[64], diff[64];
  std::vector<int> big_smooth, big_diff;
  int* t0 = smooth;
  int* t1 = diff;
  if (width > 64) {
    big_smooth.resize(static_cast<size_t>(width)), big_diff.resize(static_cast<size_t>(width));
    t0 = big_smooth.data(), t1 = big_diff.data();
  }
  const bool inside = x0 >= 1 && x1 <= cols - 1;  // no column needs reflecting
  for (int y = y0; y < y1; ++y) {
    const uchar* r0 = src.ptr<uchar>(reflect(y - 1, rows));
    const uchar* r1 = src.ptr<uchar>(y);
    const uchar* r2 = src.ptr<uchar>(reflect(y + 1, rows));
    if (inside) {
      // Straight from the three rows: a row of sums stored and read back one element off
      // stalled every vector load on store forwarding (a quarter of this function's time).
      const uchar *a = r0 + x0, *b = r1 + x0, *c = r2 + x0;
      short* out = dst.ptr<short>(y) + 2 * x0;
      for (int k = 0; k < x1 - x0; ++k) {
        const int right = (a[k + 1] + c[k + 1]) * 3 + b[k + 1] * 10;
        const int left = (a[k - 1] + c[k - 1]) * 3 + b[k - 1] * 10;
        out[2 * k] = static_cast<short>(right - left);
        out[2 * k + 1] = static_cast<short>(((c[k + 1] - a[k + 1]) + (c[k - 1] - a[k - 1])) * 3 +
                                            (c[k] - a[k]) * 10);
      }
      continue;
    }
    for (int k = 0; k < width; ++k) {
      const int x = reflect(x0 - 1 + k, cols);
      t0[k] = (r0[x] + r2[x]) * 3 + r1[x] * 10;
      t1[k] = r2[x] - r0[x];
    }
    short* out = dst.ptr<short>(y);
    for (int x = x0; x < x1; ++x) {
      const int k = x - x0 + 1;
      out[2 * x] = static_cast<short>(t0[k + 1] - t0[k - 1]);
      out[2 * x + 1] = static_cast<short>((t1[k + 1] + t1[k - 1]) * 3 + t1[k] * 10);
    }
  }
}

}  // namespace

void LkPyramid::build(const cv::Mat& image, cv::Size window, int levels) {
  window_ = window;
  levels = cv::buildOpticalFlowPyramid(image, images_, window, levels, false,
                                       cv::BORDER_REFLECT_101, cv::BORDER_CONSTANT, false);
  derivatives_.resize(static_cast<size_t>(levels) + 1);
  interleaved_.resize(2 * (static_cast<size_t>(levels) + 1));
  for (int l = 0; l <= levels; ++l) {
    const cv::Size sz = images_[static_cast<size_t>(l)].size();
    cv::Mat& d = derivatives_[static_cast<size_t>(l)];
    if (d.size() != sz) {
      // LK reads up to a window beyond the image: a zero border, as OpenCV's own.
      cv::Mat whole =
          cv::Mat::zeros(sz.height + 2 * window.height, sz.width + 2 * window.width, CV_16SC2);
      d = whole(cv::Rect(window.width, window.height, sz.width, sz.height));
    }
    interleaved_[2 * static_cast<size_t>(l)] = images_[static_cast<size_t>(l)];
    interleaved_[2 * static_cast<size_t>(l) + 1] = d;
  }
}

void LkPyramid::derivatives(const std::vector<cv::Point2f>& points) {
  // LK's window at a level starts at floor(p - half) and reads window + 1 pixels (bilinear).
  const int reach_x = window_.width / 2 + 2, reach_y = window_.height / 2 + 2;
  for (size_t l = 0; l < images_.size(); ++l) {
    const float scale = 1.0f / static_cast<float>(1 << l);
    for (const cv::Point2f& p : points) {
      const int x = static_cast<int>(std::floor(p.x * scale)),
                y = static_cast<int>(std::floor(p.y * scale));
      scharr_window(images_[l], derivatives_[l], x - reach_x, y - reach_y, x + reach_x + 1,
                    y + reach_y + 1);
    }
  }
}

}  // namespace rostro::tracking
