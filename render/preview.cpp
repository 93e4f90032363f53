#include "render/preview.hpp"

#include <algorithm>
#include <opencv2/imgproc.hpp>

namespace rostro::render {

cv::Mat compose_preview(const cv::Mat& camera, const cv::Mat& head,
                        const std::vector<std::string>& lines) {
  const int h = head.rows;
  cv::Mat scaled;
  const double scale = static_cast<double>(h) / std::max(1, camera.rows);
  cv::resize(camera, scaled, cv::Size(std::max(1, static_cast<int>(camera.cols * scale)), h), 0, 0,
             cv::INTER_AREA);
  if (scaled.channels() == 1) cv::cvtColor(scaled, scaled, cv::COLOR_GRAY2BGR);
  constexpr int kLineHeight = 20;
  const int text_rows = lines.empty() ? 0 : kLineHeight * static_cast<int>(lines.size()) + 8;
  // Even sizes: H.264 encoders refuse odd widths and heights.
  const int width = (scaled.cols + head.cols + 1) & ~1;
  const int height = (h + text_rows + 1) & ~1;
  cv::Mat view(height, width, CV_8UC3, cv::Scalar(24, 24, 24));
  scaled.copyTo(view(cv::Rect(0, 0, scaled.cols, h)));
  head.copyTo(view(cv::Rect(scaled.cols, 0, head.cols, h)));
  int y = h + kLineHeight;
  for (const auto& line : lines) {
    cv::putText(view, line, {8, y}, cv::FONT_HERSHEY_SIMPLEX, 0.5, {230, 230, 230}, 1, cv::LINE_AA);
    y += kLineHeight;
  }
  return view;
}

}  // namespace rostro::render
