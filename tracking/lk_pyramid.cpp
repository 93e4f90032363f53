#include "tracking/lk_pyramid.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <opencv2/core/hal/intrin.hpp>
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

// OpenCV's calcScharrDeriv (modules/video/src/lkpyramid.cpp) on the pixels [x0, x1) of row y
// of `src`: dx = [3 10 3]^T * [-1 0 1], dy = [-1 0 1]^T * [3 10 3], as shorts.
void scharr_row(const cv::Mat& src, cv::Mat& dst, int y, int x0, int x1) {
  const int rows = src.rows, cols = src.cols;
  const uchar* r0 = src.ptr<uchar>(reflect(y - 1, rows));
  const uchar* r1 = src.ptr<uchar>(y);
  const uchar* r2 = src.ptr<uchar>(reflect(y + 1, rows));
  short* out = dst.ptr<short>(y);
  if (x0 >= 1 && x1 <= cols - 1) {  // no column needs reflecting
    // Straight from the three rows (a row of sums stored and read back one element off
    // stalled every vector load on store forwarding).
    const uchar *a = r0 + x0, *b = r1 + x0, *c = r2 + x0;
    out += 2 * x0;
    int k = 0;
#if CV_SIMD128
    // Eight pixels at a time, as OpenCV's own loop (the compiler does not vectorise the
    // interleaved store). Sums stay below 4096: 16-bit arithmetic is exact.
    using cv::v_int16x8;
    auto row8 = [](const uchar* p) { return cv::v_reinterpret_as_s16(cv::v_load_expand(p)); };
    const v_int16x8 three = cv::v_setall_s16(3), ten = cv::v_setall_s16(10);
    for (; k + 8 <= x1 - x0; k += 8) {
      const v_int16x8 al = row8(a + k - 1), am = row8(a + k), ar = row8(a + k + 1);
      const v_int16x8 bl = row8(b + k - 1), br = row8(b + k + 1);
      const v_int16x8 cl = row8(c + k - 1), cm = row8(c + k), cr = row8(c + k + 1);
      const v_int16x8 dx = cv::v_mul_wrap(ar + cr - al - cl, three) + cv::v_mul_wrap(br - bl, ten);
      const v_int16x8 dy = cv::v_mul_wrap(cr - ar + cl - al, three) + cv::v_mul_wrap(cm - am, ten);
      cv::v_store_interleave(out + 2 * k, dx, dy);
    }
#endif
    for (; k < x1 - x0; ++k) {
      const int right = (a[k + 1] + c[k + 1]) * 3 + b[k + 1] * 10;
      const int left = (a[k - 1] + c[k - 1]) * 3 + b[k - 1] * 10;
      out[2 * k] = static_cast<short>(right - left);
      out[2 * k + 1] = static_cast<short>(((c[k + 1] - a[k + 1]) + (c[k - 1] - a[k - 1])) * 3 +
                                          (c[k] - a[k]) * 10);
    }
    return;
  }
  for (int x = x0; x < x1; ++x) {
    const int l = reflect(x - 1, cols), r = reflect(x + 1, cols);
    out[2 * x] =
        static_cast<short>((r0[r] + r2[r]) * 3 + r1[r] * 10 - ((r0[l] + r2[l]) * 3 + r1[l] * 10));
    out[2 * x + 1] =
        static_cast<short>(((r2[r] - r0[r]) + (r2[l] - r0[l])) * 3 + (r2[x] - r0[x]) * 10);
  }
}

// The derivatives of [x0, x1) x [y0, y1) not yet filled since the level was built: the windows
// of neighbouring points overlap, and a pyramid is read twice, as the second image of one
// frame's LK and the first of the next, around nearly the same points. `filled` holds a bit
// per pixel, 64 to a word, rows of `words` words.
void scharr_window(const cv::Mat& src, cv::Mat& dst, uint64_t* filled, int words, int x0, int y0,
                   int x1, int y1) {
  x0 = std::max(x0, 0), y0 = std::max(y0, 0);
  x1 = std::min(x1, src.cols), y1 = std::min(y1, src.rows);
  for (int y = y0; y < y1; ++y) {
    uint64_t* row = filled + static_cast<ptrdiff_t>(y) * words;
    for (int x = x0; x < x1;) {
      uint64_t& word = row[x >> 6];
      const int bit = x & 63;
      const uint64_t open = ~word >> bit;  // pixels from x to the word's end not yet filled
      if (open == 0) {
        x += 64 - bit;
        continue;
      }
      const int start = x + std::countr_zero(open);
      if (start >= x1) break;
      const uint64_t done = word >> (start & 63);
      const int end = std::min(x1, done == 0 ? (x & ~63) + 64 : start + std::countr_zero(done));
      const int n = end - start;
      word |= (n == 64 ? ~uint64_t{0} : ((uint64_t{1} << n) - 1)) << (start & 63);
      scharr_row(src, dst, y, start, end);
      x = end;
    }
  }
}

}  // namespace

void LkPyramid::build(const cv::Mat& image, cv::Size window, int levels) {
  window_ = window;
  levels = cv::buildOpticalFlowPyramid(image, images_, window, levels, false,
                                       cv::BORDER_REFLECT_101, cv::BORDER_CONSTANT, false);
  derivatives_.resize(static_cast<size_t>(levels) + 1);
  filled_.resize(static_cast<size_t>(levels) + 1);
  for (int l = 0; l <= levels; ++l) {
    const cv::Size sz = images_[static_cast<size_t>(l)].size();
    filled_[static_cast<size_t>(l)].assign(static_cast<size_t>(sz.height) * words(sz.width), 0);
  }
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
      scharr_window(images_[l], derivatives_[l], filled_[l].data(),
                    static_cast<int>(words(images_[l].cols)), x - reach_x, y - reach_y,
                    x + reach_x + 1, y + reach_y + 1);
    }
  }
}

}  // namespace rostro::tracking
