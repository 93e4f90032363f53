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

double LandmarkStabiliser::predict(const cv::Mat& gray, double eyes) {
  predicted_.clear();
  if (previous_.empty() || !(eyes > 0) || previous_gray_.size() != gray.size()) return 0;
  // The flow only where the face is: the last points' box, grown by a window and the largest
  // motion LK's pyramid reaches.
  const cv::Rect2d around =
      cv::boundingRect(std::vector<cv::Point2f>(previous_.begin(), previous_.end()));
  const double margin = options_.lk_window * (1 << options_.lk_levels);
  const cv::Rect roi =
      cv::Rect(cv::Point(static_cast<int>(around.x - margin), static_cast<int>(around.y - margin)),
               cv::Point(static_cast<int>(around.br().x + margin),
                         static_cast<int>(around.br().y + margin))) &
      cv::Rect(0, 0, gray.cols, gray.rows);
  if (roi.width < options_.lk_window || roi.height < options_.lk_window) return 0;
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
  if (moved_from.size() < 6) return 0;
  std::vector<unsigned char> inlier;
  const cv::Mat m =
      cv::estimateAffinePartial2D(moved_from, moved_to, inlier, cv::RANSAC, 0.02 * eyes);
  if (m.empty()) return 0;
  for (const cv::Point2f& q : from)
    predicted_.emplace_back(
        m.at<double>(0, 0) * q.x + m.at<double>(0, 1) * q.y + m.at<double>(0, 2) + roi.x,
        m.at<double>(1, 0) * q.x + m.at<double>(1, 1) * q.y + m.at<double>(1, 2) + roi.y);
  return static_cast<double>(std::count(inlier.begin(), inlier.end(), 1)) /
         static_cast<double>(previous_.size());
}

std::vector<cv::Point2d> LandmarkStabiliser::blend(const cv::Mat& gray,
                                                   const std::vector<cv::Point2d>& fit,
                                                   double eyes) {
  std::vector<cv::Point2d> out = fit;
  if (predicted_.size() == fit.size() && eyes > 0)
    for (std::size_t i = 0; i < fit.size(); ++i) {
      const cv::Point2d towards_fit = fit[i] - predicted_[i];
      const double apart = std::min(1.0, cv::norm(towards_fit) / eyes / options_.full_trust);
      const double w = options_.follow_share + (1 - options_.follow_share) * apart * apart;
      out[i] = predicted_[i] + w * towards_fit;
    }
  gray.copyTo(previous_gray_);
  previous_ = out;
  return out;
}

}  // namespace rostro::tracking
