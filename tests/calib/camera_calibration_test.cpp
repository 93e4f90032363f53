// Chessboard calibration on boards rendered by the test (a drawn board warped by the
// homography of a known camera and pose), and intrinsics files.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "calib/chessboard_calibration.hpp"
#include "facecore/error.hpp"

namespace rostro::calib {
namespace {

constexpr int kSquarePx = 40;  // board image: pixels per square
constexpr int kMarginPx = 40;
constexpr double kSquareMm = 25;

// A flat board with 10 x 7 squares (9 x 6 inner corners) and a white margin.
cv::Mat board_image() {
  cv::Mat board(7 * kSquarePx + 2 * kMarginPx, 10 * kSquarePx + 2 * kMarginPx, CV_8UC1,
                cv::Scalar(255));
  for (int r = 0; r < 7; ++r)
    for (int c = 0; c < 10; ++c)
      if ((r + c) % 2 == 0)
        cv::rectangle(
            board,
            cv::Rect(kMarginPx + c * kSquarePx, kMarginPx + r * kSquarePx, kSquarePx, kSquarePx),
            cv::Scalar(0), cv::FILLED);
  return board;
}

// The board seen by camera K from pose (rvec, tvec); board mm origin at its first inner corner.
cv::Mat view(const cv::Mat& board, const cv::Matx33d& K, cv::Vec3d rvec, cv::Vec3d tvec,
             cv::Size size) {
  cv::Matx33d R;
  cv::Rodrigues(rvec, R);
  // Board pixel -> board mm (z = 0): X = (px - margin - square) * mm per px.
  const double s = kSquareMm / kSquarePx;
  const double o = kMarginPx + kSquarePx;
  const cv::Matx33d to_mm(s, 0, -o * s, 0, s, -o * s, 0, 0, 1);
  const cv::Matx33d extrinsic(R(0, 0), R(0, 1), tvec[0], R(1, 0), R(1, 1), tvec[1], R(2, 0),
                              R(2, 1), tvec[2]);
  const cv::Matx33d H = K * extrinsic * to_mm;
  cv::Mat out;
  cv::warpPerspective(board, out, cv::Mat(H), size, cv::INTER_LINEAR, cv::BORDER_CONSTANT,
                      cv::Scalar(128));
  cv::GaussianBlur(out, out, {3, 3}, 0.7);
  return out;
}

TEST(ChessboardCalibration, RecoversTheFocalLengthFromRenderedBoards) {
  const cv::Size size(800, 600);
  const cv::Matx33d K(700, 0, 410, 0, 700, 295, 0, 0, 1);
  const cv::Mat board = board_image();
  std::vector<cv::Mat> images;
  const double tilts[][3] = {{0.0, 0.0, 0.0},    {0.35, 0.0, 0.05}, {-0.35, 0.1, 0.0},
                             {0.0, 0.4, -0.1},   {0.1, -0.4, 0.0},  {0.3, 0.3, 0.2},
                             {-0.3, -0.25, 0.1}, {0.2, -0.2, -0.2}};
  for (const auto& t : tilts)
    images.push_back(view(board, K, {t[0], t[1], t[2]}, {-110, -60, 450}, size));
  images.push_back(cv::Mat(size, CV_8UC1, cv::Scalar(128)));  // no board: rejected

  const ChessboardCalibration c = calibrate_camera(images, {{9, 6}, kSquareMm});
  EXPECT_EQ(c.views_used, 8);
  EXPECT_EQ(c.views_rejected, 1);
  EXPECT_NEAR(c.intrinsics.fx, 700, 0.03 * 700);
  EXPECT_NEAR(c.intrinsics.fy, 700, 0.03 * 700);
  EXPECT_NEAR(c.intrinsics.cx, 410, 15);
  EXPECT_NEAR(c.intrinsics.cy, 295, 15);
  EXPECT_LT(c.intrinsics.reprojection_error, 0.5);
  EXPECT_EQ(c.intrinsics.image_size, size);
}

TEST(ChessboardCalibration, TooFewViewsOrMixedSizesAreErrors) {
  const cv::Mat blank(480, 640, CV_8UC1, cv::Scalar(200));
  EXPECT_THROW(calibrate_camera({blank, blank, blank}, {}), InputError);
  EXPECT_THROW(calibrate_camera({blank, cv::Mat(100, 100, CV_8UC1)}, {}), InputError);
  EXPECT_THROW(calibrate_camera({blank}, {{1, 6}, 25}), InputError);
}

TEST(CameraIntrinsics, FileStorageRoundTripInYamlAndJson) {
  CameraIntrinsics k;
  k.image_size = {1920, 1080};
  k.fx = 1400.5;
  k.fy = 1398.25;
  k.cx = 960.5;
  k.cy = 541;
  k.distortion = {0.05, -0.1, 0.001, -0.002, 0.02};
  k.reprojection_error = 0.27;
  k.source = "chessboard 9x6, 10 views";
  for (const char* ext : {".yml", ".json", ".xml"}) {
    const auto path = std::filesystem::path(ROSTRO_BINARY_DIR) / (std::string("test_camera") + ext);
    write_intrinsics(path, k);
    const CameraIntrinsics r = read_intrinsics(path);
    EXPECT_EQ(r.image_size, k.image_size) << ext;
    EXPECT_DOUBLE_EQ(r.fx, k.fx) << ext;
    EXPECT_DOUBLE_EQ(r.cy, k.cy) << ext;
    EXPECT_EQ(r.distortion, k.distortion) << ext;
    EXPECT_DOUBLE_EQ(r.reprojection_error, k.reprojection_error) << ext;
    EXPECT_EQ(r.source, k.source) << ext;
    std::filesystem::remove(path);
  }
  EXPECT_THROW(write_intrinsics(std::filesystem::path(ROSTRO_BINARY_DIR) / "camera.txt", k),
               InputError);
}

TEST(CameraIntrinsics, MalformedFilesAndTheDefault) {
  const auto path = std::filesystem::path(ROSTRO_BINARY_DIR) / "test_camera_bad.yml";
  { std::ofstream(path) << "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\n"; }
  try {
    read_intrinsics(path);
    FAIL() << "no error for a file without camera_matrix";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("camera_matrix"), std::string::npos) << e.what();
  }
  { std::ofstream(path) << "this is not yaml: [\n"; }
  EXPECT_THROW(read_intrinsics(path), InputError);
  std::filesystem::remove(path);
  EXPECT_THROW(read_intrinsics("/nonexistent/camera.yml"), InputError);

  const CameraIntrinsics d = default_intrinsics({1280, 720});
  EXPECT_EQ(d.fx, 1280);
  EXPECT_EQ(d.cx, 640);
  EXPECT_EQ(d.cy, 360);
  EXPECT_FALSE(d.has_distortion());
  // The fit refines a default focal length from head turns, never a calibrated one.
  EXPECT_TRUE(is_default_intrinsics(d));
  CameraIntrinsics calibrated = d;
  calibrated.source = "chessboard, 12 views";
  EXPECT_FALSE(is_default_intrinsics(calibrated));
}

// Found by fuzz_intrinsics: a damaged matrix size asked OpenCV for gigabytes, and a damaged
// file ended in std::length_error out of OpenCV's parser; both are one InputError now.
TEST(CameraIntrinsics, DamagedFilesFromMemoryAreInputErrors) {
  const std::string good =
      "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\n"
      "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
      "   data: [ 1000., 0., 320., 0., 1000., 240., 0., 0., 1. ]\n";
  EXPECT_EQ(parse_intrinsics(good, "mem.yml").fx, 1000);
  std::string huge = good;
  huge.replace(huge.find("cols: 3"), 7, "cols: 1000000000");
  try {
    parse_intrinsics(huge, "mem.yml");
    FAIL() << "no error for a matrix of a billion columns";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("mem.yml: 'camera_matrix' declares 3x1000000000"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(parse_intrinsics("", "mem.yml"), InputError);
}

TEST(CameraIntrinsics, FramesOfAnotherSizeAreScaledOrRefused) {
  CameraIntrinsics hd;
  hd.image_size = {1280, 720};
  hd.fx = hd.fy = 1000;
  hd.cx = 639.5;
  hd.cy = 359.5;
  std::string note;
  EXPECT_EQ(intrinsics_for_frames(hd, {1280, 720}, "cam.yml", &note).fx, 1000);
  EXPECT_TRUE(note.empty());

  // Half size, same aspect: the image resized, so the intrinsics scale with it.
  const CameraIntrinsics half = intrinsics_for_frames(hd, {640, 360}, "cam.yml", &note);
  EXPECT_DOUBLE_EQ(half.fx, 500);
  EXPECT_DOUBLE_EQ(half.cx, 319.5);  // the centre stays the centre
  EXPECT_DOUBLE_EQ(half.cy, 179.5);
  EXPECT_EQ(half.image_size, cv::Size(640, 360));
  EXPECT_NE(note.find("scaled"), std::string::npos) << note;

  // 4:3 frames from 16:9 intrinsics: refused, naming both sizes.
  try {
    intrinsics_for_frames(hd, {640, 480}, "cam.yml", &note);
    FAIL() << "640x480 frames accepted 1280x720 intrinsics";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("cam.yml"), std::string::npos) << what;
    EXPECT_NE(what.find("1280x720"), std::string::npos) << what;
    EXPECT_NE(what.find("640x480"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace rostro::calib
