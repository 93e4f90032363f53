#pragma once
// Camera intrinsics from views of a printed chessboard (cv::findChessboardCorners, sub-pixel
// refinement, cv::calibrateCamera), with the RMS reprojection error as the quality figure.

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "calib/camera_intrinsics.hpp"

namespace rostro::calib {

struct ChessboardSpec {
  cv::Size inner_corners{9, 6};  // corners where four squares meet, per row and column
  double square_size_mm = 25.0;
};

struct ChessboardCalibration {
  CameraIntrinsics intrinsics;  // reprojection_error filled in
  int views_used = 0;           // images where the whole board was found
  int views_rejected = 0;       // images where it was not
};

// Finds the board in one image; empty when it is not (fully) visible.
std::vector<cv::Point2f> find_chessboard(const cv::Mat& image, cv::Size inner_corners);

struct ChessboardOptions {
  int min_views = 3;
  // Estimate only k1 k2 (p1 = p2 = k3 = 0): few views cannot pin down more.
  bool simple_distortion = true;
};

// Throws InputError when the images differ in size or fewer than min_views show the board.
ChessboardCalibration calibrate_camera(const std::vector<cv::Mat>& images,
                                       const ChessboardSpec& board,
                                       const ChessboardOptions& options = {});

}  // namespace rostro::calib
