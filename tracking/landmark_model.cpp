#include "tracking/landmark_model.hpp"

#include <dlib/image_processing/frontal_face_detector.h>
#include <dlib/image_processing/shape_predictor.h>
#include <dlib/opencv/cv_image.h>
#include <dlib/serialize.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <fstream>
#include <opencv2/imgproc.hpp>
#include <string>

#include "facecore/error.hpp"

namespace rostro::tracking {

std::filesystem::path default_landmark_model() {
  return "/usr/share/dlib/shape_predictor_68_face_landmarks.dat";
}

// dlib::shape_predictor's own members and cascade, read from the same file format, so that
// the landmarks come out in sub-pixel floats: dlib's operator() rounds them to whole pixels
// (dlib::point), a 0.5 px step that no filter downstream can take back.
struct SubpixelShapePredictor {
  dlib::matrix<float, 0, 1> initial_shape;
  std::vector<std::vector<dlib::impl::regression_tree>> forests;
  std::vector<std::vector<unsigned long>> anchor_idx;
  std::vector<std::vector<dlib::vector<float, 2>>> deltas;

  unsigned long num_parts() const { return initial_shape.size() / 2; }

  // As dlib's deserialize(shape_predictor&).
  void read(std::istream& in) {
    int version = 0;
    dlib::deserialize(version, in);
    if (version != 1)
      throw dlib::serialization_error("unexpected shape_predictor version " +
                                      std::to_string(version));
    dlib::deserialize(initial_shape, in);
    dlib::deserialize(forests, in);
    dlib::deserialize(anchor_idx, in);
    dlib::deserialize(deltas, in);
  }

  // As dlib's shape_predictor::operator(), without the rounding.
  template <typename Image>
  std::vector<cv::Point2d> operator()(const Image& img, const dlib::rectangle& rect) const {
    dlib::matrix<float, 0, 1> shape = initial_shape;
    std::vector<float> features;
    for (unsigned long level = 0; level < forests.size(); ++level) {
      dlib::impl::extract_feature_pixel_values(img, rect, shape, initial_shape, anchor_idx[level],
                                               deltas[level], features);
      unsigned long leaf = 0;
      for (const dlib::impl::regression_tree& tree : forests[level]) shape += tree(features, leaf);
    }
    const dlib::point_transform_affine to_image = dlib::impl::unnormalizing_tform(rect);
    std::vector<cv::Point2d> points(num_parts());
    for (unsigned long i = 0; i < points.size(); ++i) {
      const dlib::vector<double, 2> p = to_image(dlib::impl::location(shape, i));
      points[i] = {p.x(), p.y()};
    }
    return points;
  }
};

struct LandmarkModel::Impl {
  dlib::frontal_face_detector detector = dlib::get_frontal_face_detector();
  SubpixelShapePredictor predictor;
};

LandmarkModel::LandmarkModel(const std::filesystem::path& model) : impl_(std::make_unique<Impl>()) {
  const std::string name = model.string();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(model, ec))
    throw InputError(name + ": no landmark model there (Debian's libdlib-data installs the " +
                     "68-point model at " + default_landmark_model().string() +
                     "; --landmark-model names another)");
  try {
    std::ifstream in(model, std::ios::binary);
    impl_->predictor.read(in);
  } catch (const std::exception& e) {
    std::string why = e.what();
    why = why.substr(0, why.find('\n'));
    throw InputError(name + ": not a dlib shape predictor model (" + why.substr(0, 100) + ")");
  }
  if (impl_->predictor.num_parts() != kLandmarks)
    throw InputError(name + ": the model gives " + std::to_string(impl_->predictor.num_parts()) +
                     " landmarks; rostro needs the 68-point iBUG scheme");
}

LandmarkModel::~LandmarkModel() = default;

std::vector<FaceDetection> LandmarkModel::detect(const cv::Mat& gray, const cv::Rect& roi,
                                                 double face_px, double threshold) {
  const double scale = std::min(2.0, kDetectorWindowPx / face_px);
  const cv::Mat view = gray(roi);
  cv::Mat scaled = view;
  if (std::abs(scale - 1.0) > 1e-3)
    cv::resize(view, scaled, {}, scale, scale, scale < 1 ? cv::INTER_AREA : cv::INTER_LINEAR);
  std::vector<dlib::rect_detection> found;
  impl_->detector(dlib::cv_image<unsigned char>(scaled), found, threshold);
  std::vector<FaceDetection> out;
  for (const dlib::rect_detection& d : found) {
    const dlib::rectangle& r = d.rect;
    out.push_back(
        {{roi.x + static_cast<double>(r.left()) / scale,
          roi.y + static_cast<double>(r.top()) / scale, static_cast<double>(r.width()) / scale,
          static_cast<double>(r.height()) / scale},
         d.detection_confidence});
  }
  return out;
}

std::vector<cv::Point2d> LandmarkModel::fit(const cv::Mat& gray, const cv::Rect2d& box) const {
  const dlib::rectangle rect(std::lround(box.x), std::lround(box.y),
                             std::lround(box.x + box.width) - 1,
                             std::lround(box.y + box.height) - 1);
  return impl_->predictor(dlib::cv_image<unsigned char>(gray), rect);
}

std::vector<cv::Point2d> LandmarkModel::mean_shape() const {
  const dlib::matrix<float, 0, 1>& shape = impl_->predictor.initial_shape;
  std::vector<cv::Point2d> points(static_cast<size_t>(shape.size() / 2));
  for (size_t i = 0; i < points.size(); ++i)
    points[i] = {shape(static_cast<long>(2 * i)), shape(static_cast<long>(2 * i + 1))};
  return points;
}

}  // namespace rostro::tracking
