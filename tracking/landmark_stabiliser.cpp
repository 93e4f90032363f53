#include "tracking/landmark_stabiliser.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/video/tracking.hpp>
#include <string>

#include "facecore/error.hpp"

namespace rostro::tracking {

void StabiliserOptions::validate() const {
  if (!(follow_share > 0 && follow_share <= 1))
    throw InputError("landmark stabiliser: follow_share is a share in (0, 1], not " +
                     std::to_string(follow_share));
  if (!(full_trust > 0) || !std::isfinite(full_trust))
    throw InputError("landmark stabiliser: full_trust must be positive, not " +
                     std::to_string(full_trust));
  if (lk_window < 5 || lk_levels < 0 || lk_levels > 5)
    throw InputError("landmark stabiliser: LK window of at least 5 px and 0-5 levels");
}

LandmarkStabiliser::LandmarkStabiliser(StabiliserOptions options) : options_(options) {
  options_.validate();
}

std::vector<cv::Point2d> LandmarkStabiliser::update(const cv::Mat& gray,
                                                    const std::vector<cv::Point2d>& fit,
                                                    double eyes) {
  std::vector<cv::Point2d> out = fit;
  if (!previous_.empty() && previous_.size() == fit.size() && eyes > 0 &&
      previous_gray_.size() == gray.size()) {
    // The flow only where the face is: the last points' box, grown by a window and the
    // largest motion LK's pyramid reaches.
    cv::Rect2d around =
        cv::boundingRect(std::vector<cv::Point2f>(previous_.begin(), previous_.end()));
    const double margin = options_.lk_window * (1 << options_.lk_levels);
    const cv::Rect roi = cv::Rect(cv::Point(static_cast<int>(around.x - margin),
                                            static_cast<int>(around.y - margin)),
                                  cv::Point(static_cast<int>(around.br().x + margin),
                                            static_cast<int>(around.br().y + margin))) &
                         cv::Rect(0, 0, gray.cols, gray.rows);
    std::vector<cv::Point2f> from, to;
    for (const cv::Point2d& p : previous_)
      from.emplace_back(static_cast<float>(p.x - roi.x), static_cast<float>(p.y - roi.y));
    std::vector<unsigned char> found;
    std::vector<float> error;
    cv::calcOpticalFlowPyrLK(previous_gray_(roi), gray(roi), from, to, found, error,
                             {options_.lk_window, options_.lk_window}, options_.lk_levels);
    // The face's own motion: one similarity through the flow of all points (RANSAC), which
    // averages away the flow's noise and its slides along edges and smooth skin.
    std::vector<cv::Point2f> moved_from, moved_to;
    for (std::size_t i = 0; i < from.size(); ++i)
      if (found[i]) moved_from.push_back(from[i]), moved_to.push_back(to[i]);
    cv::Mat motion;
    if (moved_from.size() >= 6)
      motion =
          cv::estimateAffinePartial2D(moved_from, moved_to, cv::noArray(), cv::RANSAC, 0.02 * eyes);
    if (!motion.empty()) {
      for (std::size_t i = 0; i < fit.size(); ++i) {
        const cv::Point2d p(from[i].x, from[i].y);
        const cv::Point2d predicted(motion.at<double>(0, 0) * p.x + motion.at<double>(0, 1) * p.y +
                                        motion.at<double>(0, 2) + roi.x,
                                    motion.at<double>(1, 0) * p.x + motion.at<double>(1, 1) * p.y +
                                        motion.at<double>(1, 2) + roi.y);
        const cv::Point2d towards_fit = fit[i] - predicted;
        const double apart = std::min(1.0, cv::norm(towards_fit) / eyes / options_.full_trust);
        const double w = options_.follow_share + (1 - options_.follow_share) * apart * apart;
        out[i] = predicted + w * towards_fit;
      }
    }
  }
  gray.copyTo(previous_gray_);
  previous_ = out;
  return out;
}

}  // namespace rostro::tracking
