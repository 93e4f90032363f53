#include "calib/chessboard_calibration.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "facecore/error.hpp"

namespace rostro::calib {

std::vector<cv::Point2f> find_chessboard(const cv::Mat& image, cv::Size inner_corners) {
  cv::Mat gray;
  if (image.channels() == 3)
    cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
  else if (image.channels() == 4)
    cv::cvtColor(image, gray, cv::COLOR_BGRA2GRAY);
  else
    gray = image;
  std::vector<cv::Point2f> corners;
  const int flags = cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE;
  if (!cv::findChessboardCorners(gray, inner_corners, corners, flags)) return {};
  cv::cornerSubPix(gray, corners, {11, 11}, {-1, -1},
                   {cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 30, 0.01});
  return corners;
}

ChessboardCalibration calibrate_camera(const std::vector<cv::Mat>& images,
                                       const ChessboardSpec& board,
                                       const ChessboardOptions& options) {
  if (board.inner_corners.width < 2 || board.inner_corners.height < 2 || board.square_size_mm <= 0)
    throw InputError("chessboard: need at least 2x2 inner corners and a positive square size");
  std::vector<cv::Point3f> object;
  for (int r = 0; r < board.inner_corners.height; ++r)
    for (int c = 0; c < board.inner_corners.width; ++c)
      object.emplace_back(static_cast<float>(c * board.square_size_mm),
                          static_cast<float>(r * board.square_size_mm), 0.0f);

  ChessboardCalibration result;
  cv::Size size;
  std::vector<std::vector<cv::Point3f>> object_points;
  std::vector<std::vector<cv::Point2f>> image_points;
  for (std::size_t i = 0; i < images.size(); ++i) {
    if (images[i].empty()) throw InputError("chessboard: image " + std::to_string(i) + " is empty");
    if (size.area() == 0) size = images[i].size();
    if (images[i].size() != size)
      throw InputError("chessboard: image " + std::to_string(i) + " is " +
                       std::to_string(images[i].cols) + "x" + std::to_string(images[i].rows) +
                       ", expected " + std::to_string(size.width) + "x" +
                       std::to_string(size.height) + " like the first");
    auto corners = find_chessboard(images[i], board.inner_corners);
    if (corners.empty()) {
      ++result.views_rejected;
      continue;
    }
    image_points.push_back(std::move(corners));
    object_points.push_back(object);
  }
  result.views_used = static_cast<int>(image_points.size());
  if (result.views_used < options.min_views)
    throw InputError("chessboard: the " + std::to_string(board.inner_corners.width) + "x" +
                     std::to_string(board.inner_corners.height) + " board was found in " +
                     std::to_string(result.views_used) + " of " + std::to_string(images.size()) +
                     " images; at least " + std::to_string(options.min_views) + " are needed");

  cv::Mat K, dist;
  std::vector<cv::Mat> rvecs, tvecs;
  int flags = 0;
  if (options.simple_distortion) flags |= cv::CALIB_ZERO_TANGENT_DIST | cv::CALIB_FIX_K3;
  const double rms =
      cv::calibrateCamera(object_points, image_points, size, K, dist, rvecs, tvecs, flags);

  CameraIntrinsics& k = result.intrinsics;
  k.image_size = size;
  k.fx = K.at<double>(0, 0);
  k.fy = K.at<double>(1, 1);
  k.cx = K.at<double>(0, 2);
  k.cy = K.at<double>(1, 2);
  dist = dist.reshape(1, 1);
  k.distortion.assign(dist.begin<double>(), dist.end<double>());
  k.reprojection_error = rms;
  k.source = "chessboard " + std::to_string(board.inner_corners.width) + "x" +
             std::to_string(board.inner_corners.height) + ", " + std::to_string(result.views_used) +
             " views";
  return result;
}

}  // namespace rostro::calib
