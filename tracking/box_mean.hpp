#pragma once
// The 3x3 mean of a float image over part of it only, equal to the bit to cv::blur(src, dst,
// {3, 3}) there when the image holds whole numbers (as a dot's contrast window does: grey
// levels minus a median grey level).
//
// Why: a dot's contrast window is as wide as the largest dot allowed, but its smoothed copy is
// read only around the guess (where the dot's core is looked for), a tenth of the window; and
// cv::blur builds a filter engine on every call, which at 40-odd calls a frame cost more than
// the sums themselves. cv::blur on 32-bit floats sums in double (exact for whole numbers of
// this size, in any order) and multiplies the sum by 1/9 before rounding to float, as here;
// pixels at the image's edge see their neighbours reflected (BORDER_REFLECT_101) as there.

#include <algorithm>
#include <opencv2/core.hpp>

namespace rostro::tracking {

// Fills `dst` (CV_32F, src's size) inside `area` only; the rest of dst is left as it was.
inline void box3_mean(const cv::Mat& src, cv::Mat& dst, cv::Rect area) {
  CV_Assert(src.type() == CV_32FC1 && dst.type() == CV_32FC1 && dst.size() == src.size());
  area &= cv::Rect(0, 0, src.cols, src.rows);
  if (area.empty()) return;
  const int rows = src.rows, cols = src.cols;
  auto reflect = [](int i, int n) { return n == 1 ? 0 : i < 0 ? -i : i >= n ? 2 * n - 2 - i : i; };
  // Columns whose both neighbours are inside: summed in float (whole numbers up to 9 x 255 are
  // exact there too) and vectorised; the image's first and last columns through reflect().
  const int inner0 = std::max(area.x, 1), inner1 = std::min(area.x + area.width, cols - 1);
  for (int y = area.y; y < area.y + area.height; ++y) {
    const float* r0 = src.ptr<float>(reflect(y - 1, rows));
    const float* r1 = src.ptr<float>(y);
    const float* r2 = src.ptr<float>(reflect(y + 1, rows));
    float* out = dst.ptr<float>(y);
    auto at_edge = [&](int x) {
      const int xl = reflect(x - 1, cols), xr = reflect(x + 1, cols);
      const double sum = (static_cast<double>(r0[xl]) + r0[x] + r0[xr]) +
                         (static_cast<double>(r1[xl]) + r1[x] + r1[xr]) +
                         (static_cast<double>(r2[xl]) + r2[x] + r2[xr]);
      out[x] = static_cast<float>(sum * (1. / 9));
    };
    for (int x = area.x; x < std::min(inner0, area.x + area.width); ++x) at_edge(x);
    for (int x = inner0; x < inner1; ++x) {
      const float sum = (r0[x - 1] + r1[x - 1] + r2[x - 1]) + (r0[x] + r1[x] + r2[x]) +
                        (r0[x + 1] + r1[x + 1] + r2[x + 1]);
      out[x] = static_cast<float>(static_cast<double>(sum) * (1. / 9));
    }
    for (int x = std::max(inner1, area.x); x < area.x + area.width; ++x) at_edge(x);
  }
}

}  // namespace rostro::tracking
