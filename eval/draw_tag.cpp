#include "eval/draw_tag.hpp"

#include <opencv2/imgproc.hpp>
#include <vector>

#include "tracking/apriltag_detector.hpp"

namespace rostro::eval {

void draw_tag(cv::Mat& image, const tracking::MarkerSpec& spec,
              const std::array<cv::Point2d, 4>& corners) {
  const cv::Mat bits = tracking::apriltag_image(spec.family, spec.tag_id);
  const int cell = 12;
  cv::Mat big;
  cv::resize(bits, big, {}, cell, cell, cv::INTER_NEAREST);
  // Paper is not 255 and ink not 0: the renderer's skin sits in between.
  big.convertTo(big, CV_8U, (235.0 - 30.0) / 255.0, 30.0);
  cv::Mat tag;
  cv::cvtColor(big, tag, cv::COLOR_GRAY2BGR);
  const int black = tracking::apriltag_black_width(spec.family);
  const double border = (bits.cols - black) / 2.0 * cell;
  const double lo = border - 0.5, hi = border + black * cell - 0.5;
  const std::vector<cv::Point2f> src = {{float(lo), float(hi)},
                                        {float(hi), float(hi)},
                                        {float(hi), float(lo)},
                                        {float(lo), float(lo)}};
  std::vector<cv::Point2f> dst;
  for (const auto& c : corners) dst.emplace_back(c);
  const cv::Mat h = cv::getPerspectiveTransform(src, dst);
  // Only the tag's bounding box (its whole sheet, border included) is warped.
  std::vector<cv::Point2f> sheet = {{-0.5f, -0.5f},
                                    {float(tag.cols) - 0.5f, -0.5f},
                                    {float(tag.cols) - 0.5f, float(tag.rows) - 0.5f},
                                    {-0.5f, float(tag.rows) - 0.5f}},
                           out;
  cv::perspectiveTransform(sheet, out, h);
  const cv::Rect box = cv::boundingRect(out) & cv::Rect(0, 0, image.cols, image.rows);
  if (box.area() <= 0) return;
  cv::Mat shift = (cv::Mat_<double>(3, 3) << 1, 0, -box.x, 0, 1, -box.y, 0, 0, 1);
  cv::Mat roi = image(box);
  cv::warpPerspective(tag, roi, shift * h, box.size(), cv::INTER_AREA, cv::BORDER_TRANSPARENT);
}

}  // namespace rostro::eval
