#include "tracking/face_prior.hpp"

#include <algorithm>
#include <mutex>

#include "facecore/error.hpp"
#include "tracking/landmark_model.hpp"

namespace rostro::tracking {
namespace {

// The model file is large (about 100 MB) and slow to read: one copy per process and file.
std::shared_ptr<LandmarkModel> shared_model(const std::filesystem::path& path) {
  static std::mutex mutex;
  static std::map<std::filesystem::path, std::shared_ptr<LandmarkModel>> models;
  const std::lock_guard lock(mutex);
  auto it = models.find(path);
  if (it != models.end()) return it->second;
  std::shared_ptr<LandmarkModel> model;
  try {
    model = std::make_shared<LandmarkModel>(path);
  } catch (const InputError&) {
    model = nullptr;  // remembered: no second attempt
  }
  models[path] = model;
  return model;
}

}  // namespace

FacePrior::FacePrior(const std::filesystem::path& model) {
  if (!model.empty()) model_ = shared_model(model);
  if (model_) mapping_ = default_ibug_mapping();
}
FacePrior::~FacePrior() = default;

bool FacePrior::available() const {
  return model_ != nullptr;
}

std::map<std::string, cv::Point2d> FacePrior::expected(const cv::Mat& gray,
                                                       const MarkerLayout& layout,
                                                       std::optional<cv::Point2d> near,
                                                       double face_px) {
  if (!model_) return {};
  // The detector's window is its smallest face: a face about face_px wide fills it at 1.25x.
  const double smallest = std::max(LandmarkModel::kDetectorWindowPx, 0.8 * face_px);
  const auto faces = model_->detect(gray, cv::Rect(0, 0, gray.cols, gray.rows), smallest, 0.0);
  if (faces.empty()) return {};
  // (does not hold `near`, distance from it), or (0, -area) without `near`: least first.
  auto distance = [&](const FaceDetection& f) {
    if (!near) return std::pair{0.0, -f.box.area()};
    const cv::Point2d centre(f.box.x + f.box.width / 2, f.box.y + f.box.height / 2);
    return std::pair{f.box.contains(*near) ? 0.0 : 1.0, cv::norm(centre - *near)};
  };
  const FaceDetection& face = *std::min_element(
      faces.begin(), faces.end(),
      [&](const FaceDetection& a, const FaceDetection& b) { return distance(a) < distance(b); });
  const std::vector<cv::Point2d> landmarks = model_->fit(gray, face.box);
  std::map<std::string, cv::Point2d> out;
  for (const MarkerSpec& m : layout.markers) {
    if (m.kind != MarkerKind::Dot) continue;
    for (const IbugMarker& i : mapping_.markers)
      if (i.feature_point == m.feature_point) out[m.id] = mapped_position(i, landmarks);
  }
  return out;
}

}  // namespace rostro::tracking
