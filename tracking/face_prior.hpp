#pragma once
// Where this face puts the layout's dots, before any is named: dlib's 68 landmarks
// (landmark_model.hpp) fitted to the face the markers are on, each layout dot whose feature
// point the iBUG mapping names (ibug_mapping.hpp) at its landmark(s). A real face is not the
// layout's average frontal arrangement (a wide mouth, a long jaw, a smile, a turn), and the
// landmarks follow the face's own shape where an affine map of the layout cannot; the dots
// are then named near these places (identify.hpp). The dots themselves sit a little off the
// landmarks (above the brow hair, beside the eye corners), which the naming allows for.

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

  // Layout dot id -> pixels, on the face found in the 8-bit grey `gray` whose box holds `near`
  // (or lies nearest it; the largest without `near`), searched for faces about `face_px` wide.
  // Empty when there is no model or no face.
  std::map<std::string, cv::Point2d> expected(const cv::Mat& gray, const MarkerLayout& layout,
                                              std::optional<cv::Point2d> near, double face_px);
  // False when the model file could not be read.
  bool available() const;

 private:
  std::shared_ptr<LandmarkModel> model_;
  IbugMapping mapping_;
};

}  // namespace rostro::tracking
