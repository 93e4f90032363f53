#pragma once
// Pinhole camera intrinsics (OpenCV model: K plus distortion coefficients) and their
// OpenCV FileStorage files (.yml/.yaml/.xml/.json), as written by `rostro calibrate camera`.

#include <filesystem>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace rostro::calib {

struct CameraIntrinsics {
  cv::Size image_size;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  std::vector<double> distortion;  // OpenCV order k1 k2 p1 p2 [k3 ...]; empty = none
  double reprojection_error = -1;  // RMS px of the calibration; -1 when not calibrated
  std::string source;              // how these were obtained ("chessboard, 12 views", ...)

  cv::Matx33d camera_matrix() const;
  bool has_distortion() const;
};

// The documented default when no calibration is given: square pixels, principal point at
// the image centre, focal length equal to the image width (a horizontal field of view of
// 2 atan(1/2) = 53 degrees, typical of webcams and phone main cameras), no distortion.
CameraIntrinsics default_intrinsics(cv::Size image_size);
// True for intrinsics made by default_intrinsics() (their focal length is a guess).
bool is_default_intrinsics(const CameraIntrinsics& intrinsics);

// Throws InputError naming the file and the missing or malformed node.
CameraIntrinsics read_intrinsics(const std::filesystem::path& path);
// The same from text in memory (YAML, XML or JSON by content); `name` stands for the path.
CameraIntrinsics parse_intrinsics(const std::string& text, const std::string& name);
// Format from the extension (.yml, .yaml, .xml, .json); written atomically.
void write_intrinsics(const std::filesystem::path& path, const CameraIntrinsics& intrinsics);

// The intrinsics for frames of `frame_size`. Unchanged when calibrated at that size; scaled
// when the frames are the calibrated image resized (the same aspect ratio within 1 %, as a
// camera mode that bins or a re-encoded video), with `*note` saying so; otherwise an
// InputError naming both sizes: a crop or another camera mode moves the principal point and
// the field of view in ways no scaling recovers (1280x720 intrinsics on 640x480 frames put a
// capture's error from 1 % to 3.8 %). `what` names the intrinsics in both messages.
CameraIntrinsics intrinsics_for_frames(const CameraIntrinsics& intrinsics, cv::Size frame_size,
                                       const std::string& what, std::string* note);

// Checks positivity and finiteness; throws InputError prefixed with `context`.
void validate_intrinsics(const CameraIntrinsics& intrinsics, const std::string& context);

}  // namespace rostro::calib
