#pragma once
// dlib's face detector and 68-point shape predictor behind a small interface, so that nothing
// else in rostro includes dlib: the HOG frontal face detector (dlib::get_frontal_face_detector)
// and a shape predictor file in dlib's format (Debian's libdlib-data ships the iBUG 300-W
// model trained by dlib's author).

#include <filesystem>
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

namespace rostro::tracking {

struct FaceDetection {
  cv::Rect2d box;         // image pixels
  double confidence = 0;  // the detector's score; 0 at its own threshold
};

// /usr/share/dlib/shape_predictor_68_face_landmarks.dat (Debian's libdlib-data).
std::filesystem::path default_landmark_model();

class LandmarkModel {
 public:
  static constexpr int kLandmarks = 68;
  static constexpr double kDetectorWindowPx = 80;  // the detector's smallest face

  // Throws InputError when the file is missing (naming the path and the Debian package),
  // is not a dlib shape predictor, or gives another number of landmarks than 68.
  explicit LandmarkModel(const std::filesystem::path& model);
  ~LandmarkModel();

  // Faces in `roi` of the 8-bit grey `gray`, searched on the region scaled so that a face
  // `face_px` wide fills the detector's window (enlarged at most twice); `threshold` adds to
  // the detector's own (negative: weaker faces too). Unordered.
  std::vector<FaceDetection> detect(const cv::Mat& gray, const cv::Rect& roi, double face_px,
                                    double threshold);
  // The 68 landmarks (pixels, iBUG order) of the face in `box`, a box as the detector gives.
  std::vector<cv::Point2d> fit(const cv::Mat& gray, const cv::Rect2d& box) const;
  // The model's average face (iBUG order) in its box as fractions of it: (0, 0) the box's top
  // left, (1, 1) its bottom right. Where a face's landmarks should lie, this gives its box.
  std::vector<cv::Point2d> mean_shape() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rostro::tracking
