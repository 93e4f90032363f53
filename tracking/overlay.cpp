#include "tracking/overlay.hpp"

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <string>

namespace rostro::tracking {

void draw_overlay(cv::Mat& image, const std::vector<MarkerState>& states, long frame) {
  if (image.channels() == 1) cv::cvtColor(image, image, cv::COLOR_GRAY2BGR);
  const cv::Scalar valid(60, 220, 60), lost(40, 40, 230);
  const double font = std::max(0.35, image.rows / 1800.0);
  int valid_count = 0;
  for (const MarkerState& s : states) {
    const bool reported = s.valid && !s.held;  // a held dot is followed, not yet reported
    if (reported) ++valid_count;
    if (!std::isfinite(s.position.x) || (!s.valid && s.lost_frames == 0)) continue;
    if (s.position == cv::Point2d()) continue;  // never seen
    const cv::Point p(static_cast<int>(std::lround(s.position.x)),
                      static_cast<int>(std::lround(s.position.y)));
    const cv::Scalar colour = reported ? valid : lost;
    if (s.spec->is_tag() && s.valid) {
      for (int k = 0; k < 4; ++k)
        cv::line(image, s.corners[k], s.corners[(k + 1) % 4], colour, 1, cv::LINE_AA);
      cv::circle(image, s.corners[0], 3, colour, -1, cv::LINE_AA);  // corner 0
    } else if (s.valid) {
      cv::drawMarker(image, p, colour, cv::MARKER_CROSS, 9, 1, cv::LINE_AA);
    } else {
      cv::circle(image, p, 7, colour, 1, cv::LINE_AA);
    }
    const std::string label =
        reported ? s.spec->id : s.spec->id + (s.held ? " found again" : " lost");
    cv::putText(image, label, p + cv::Point(6, -5), cv::FONT_HERSHEY_SIMPLEX, font, colour, 1,
                cv::LINE_AA);
  }
  const std::string status = "frame " + std::to_string(frame) + "  valid " +
                             std::to_string(valid_count) + "/" + std::to_string(states.size());
  cv::putText(image, status, {10, 24}, cv::FONT_HERSHEY_SIMPLEX, 0.6, {255, 255, 255}, 2,
              cv::LINE_AA);
}

void draw_tracked_frame(cv::Mat& image, const TrackedFrame& frame) {
  if (image.channels() == 1) cv::cvtColor(image, image, cv::COLOR_GRAY2BGR);
  const int size = std::max(9, image.rows / 60);
  for (const MarkerObservation& m : frame.markers) {
    if (!std::isfinite(m.position.x) || !std::isfinite(m.position.y)) continue;
    const cv::Point p(static_cast<int>(std::lround(m.position.x)),
                      static_cast<int>(std::lround(m.position.y)));
    if (m.valid)
      cv::drawMarker(image, p, {60, 220, 60}, cv::MARKER_CROSS, size, 2, cv::LINE_AA);
    else
      cv::circle(image, p, size / 2 + 2, {40, 40, 230}, 2, cv::LINE_AA);
  }
}

}  // namespace rostro::tracking
