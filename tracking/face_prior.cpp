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

std::map<std::string, cv::Point2d> FacePrior::expected(
    const cv::Mat& gray, const MarkerLayout& layout,
    const std::optional<cv::Matx23d>& layout_to_image) {
  if (!model_) return {};
  // The tags place the layout's origin (the nose tip) and give the face's size: about 140 mm
  // wide. Without them, a face a third of the frame wide, and the largest found.
  std::optional<cv::Point2d> near;
  double face_px = std::min(gray.cols, gray.rows) / 3.0;
  if (layout_to_image) {
    const cv::Matx23d& m = *layout_to_image;
    near = cv::Point2d(m(0, 2), m(1, 2));
    face_px = kFaceWidthMm * std::hypot(m(0, 0), m(1, 0));
  }
  // The detector's window is its smallest face: a face about face_px wide fills it at 1.25x.
  const double smallest = std::max(LandmarkModel::kDetectorWindowPx, 0.8 * face_px);
  const auto faces = model_->detect(gray, cv::Rect(0, 0, gray.cols, gray.rows), smallest, 0.0);
  std::optional<cv::Rect2d> box;
  if (near) {
    // The face the tags are on holds their nose tip; another face in the frame (a crowd, a
    // poster) does not, and its landmarks would be no evidence at all.
    for (const FaceDetection& f : faces) {
      const cv::Point2d centre(f.box.x + f.box.width / 2, f.box.y + f.box.height / 2);
      if (f.box.contains(*near) &&
          (!box || cv::norm(centre - *near) < cv::norm((box->tl() + box->br()) / 2 - *near)))
        box = f.box;
    }
  } else {
    for (const FaceDetection& f : faces)
      if (!box || f.box.area() > box->area()) box = f.box;
  }
  if (!box) return {};
  return fitted(gray, layout, *box);
}

std::map<std::string, cv::Point2d> FacePrior::fitted(const cv::Mat& gray,
                                                     const MarkerLayout& layout,
                                                     const cv::Rect2d& box) const {
  if (!model_) return {};
  const std::vector<cv::Point2d> landmarks = model_->fit(gray, box);
  std::map<std::string, cv::Point2d> out;
  for (const MarkerSpec& m : layout.markers) {
    if (m.kind != MarkerKind::Dot) continue;
    if (const IbugMarker* i = ibug_marker(m)) out[m.id] = mapped_position(*i, landmarks);
  }
  return out;
}

const IbugMarker* FacePrior::ibug_marker(const MarkerSpec& dot) const {
  for (const IbugMarker& i : mapping_.markers)
    if (i.feature_point == dot.feature_point) return &i;
  return nullptr;
}

std::optional<cv::Rect2d> FacePrior::placed_box(
    const MarkerLayout& layout, const std::map<std::string, cv::Point2d>& places) const {
  if (!model_) return std::nullopt;
  const std::vector<cv::Point2d> mean = model_->mean_shape();
  std::vector<cv::Point2d> unit, image;
  for (const auto& [id, at] : places) {
    const MarkerSpec* m = layout.find(id);
    if (m == nullptr || m->kind != MarkerKind::Dot) continue;
    if (const IbugMarker* i = ibug_marker(*m))
      unit.push_back(mapped_position(*i, mean)), image.push_back(at);
  }
  if (unit.size() < 2) return std::nullopt;
  cv::Point2d unit_mean(0, 0), image_mean(0, 0);
  for (size_t k = 0; k < unit.size(); ++k) unit_mean += unit[k], image_mean += image[k];
  unit_mean /= static_cast<double>(unit.size()), image_mean /= static_cast<double>(unit.size());
  double along = 0, spread = 0;
  for (size_t k = 0; k < unit.size(); ++k) {
    along += (unit[k] - unit_mean).dot(image[k] - image_mean);
    spread += (unit[k] - unit_mean).dot(unit[k] - unit_mean);
  }
  if (spread <= 0 || along <= 0) return std::nullopt;
  const double side = along / spread;
  const cv::Point2d origin = image_mean - side * unit_mean;
  return cv::Rect2d(origin.x, origin.y, side, side);
}

}  // namespace rostro::tracking
