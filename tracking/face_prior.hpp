#pragma once
// Where this face puts the layout's dots, before any is named: dlib's 68 landmarks
// (landmark_model.hpp) fitted to the face the markers are on, each layout dot whose feature
// point the iBUG mapping names (ibug_mapping.hpp) at its landmark(s). A real face is not the
// layout's average frontal arrangement (a wide mouth, a long jaw, a smile, a turn), and the
// landmarks follow the face's own shape where an affine map of the layout cannot; the dots
// are then named near these places (identify.hpp). The dots themselves sit a little off the
// landmarks (above the brow hair, beside the eye corners): the naming looks for each `beside`
// its landmark, as the layout says it is worn (IdentificationOptions::dots_beside_points).

#include <filesystem>
#include <map>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <string>

#include "tracking/ibug_mapping.hpp"
#include "tracking/layout.hpp"

namespace rostro::tracking {

class LandmarkModel;

class FacePrior {
 public:
  // `model`: a dlib 68-point shape predictor; a missing or unreadable file leaves the prior
  // empty (identification then goes by the layout's arrangement alone), as does an empty path.
  // The model is read here (about 0.9 s for Debian's, not in a live run's first frame), once
  // per process for every FacePrior of the same file.
  explicit FacePrior(const std::filesystem::path& model);
  ~FacePrior();

  // The face's width that sizes the detector's search from the layout's scale.
  static constexpr double kFaceWidthMm = 140;

  // Layout dot id -> pixels, on the face in the 8-bit grey `gray` that `layout_to_image` (the
  // layout's frontal millimetres to pixels, as the tags give it) puts the layout on: the
  // detected face whose box holds the layout's nose tip. Without the mapping, the largest face
  // found. Empty when there is no model or no such face.
  std::map<std::string, cv::Point2d> expected(const cv::Mat& gray, const MarkerLayout& layout,
                                              const std::optional<cv::Matx23d>& layout_to_image);
  // The same without the search: the landmarks fitted in `box` (about 1 ms, where the search
  // takes tens), as when following a face whose place is known.
  std::map<std::string, cv::Point2d> fitted(const cv::Mat& gray, const MarkerLayout& layout,
                                            const cv::Rect2d& box) const;
  // The box in which the model's average face puts the layout's dots nearest `places` (dot
  // id -> pixels; least squares over a shift and one scale: the detector's boxes are square).
  // None without a model or with fewer than two dots the model places.
  std::optional<cv::Rect2d> placed_box(const MarkerLayout& layout,
                                       const std::map<std::string, cv::Point2d>& places) const;
  // False when the model file could not be read.
  bool available() const;

 private:
  const IbugMarker* ibug_marker(const MarkerSpec& dot) const;

  std::shared_ptr<LandmarkModel> model_;
  IbugMapping mapping_;
};

}  // namespace rostro::tracking
