#include "calib/camera_intrinsics.hpp"

#include <cmath>
#include <opencv2/core/persistence.hpp>

#include "facecore/atomic_file.hpp"
#include "facecore/error.hpp"

namespace rostro::calib {

cv::Matx33d CameraIntrinsics::camera_matrix() const {
  return {fx, 0, cx, 0, fy, cy, 0, 0, 1};
}

bool CameraIntrinsics::has_distortion() const {
  for (double d : distortion)
    if (d != 0.0) return true;
  return false;
}

namespace {
constexpr const char* kDefaultSource = "default:";
}

bool is_default_intrinsics(const CameraIntrinsics& k) {
  return k.source.rfind(kDefaultSource, 0) == 0;
}

CameraIntrinsics default_intrinsics(cv::Size image_size) {
  CameraIntrinsics k;
  k.image_size = image_size;
  k.fx = k.fy = image_size.width;
  k.cx = image_size.width / 2.0;
  k.cy = image_size.height / 2.0;
  k.source = std::string(kDefaultSource) +
             " f = image width (53 degree horizontal field of view), centred, no distortion";
  return k;
}

void validate_intrinsics(const CameraIntrinsics& k, const std::string& context) {
  auto bad = [](double v) { return !std::isfinite(v) || v <= 0; };
  if (k.image_size.width <= 0 || k.image_size.height <= 0)
    throw InputError(context + ": image size must be positive");
  if (bad(k.fx) || bad(k.fy)) throw InputError(context + ": focal lengths must be positive");
  if (!std::isfinite(k.cx) || !std::isfinite(k.cy))
    throw InputError(context + ": principal point must be finite");
  for (double d : k.distortion)
    if (!std::isfinite(d)) throw InputError(context + ": distortion coefficients must be finite");
}

CameraIntrinsics read_intrinsics(const std::filesystem::path& path) {
  const std::string name = path.string();
  if (!std::filesystem::exists(path)) throw InputError(name + ": camera intrinsics file not found");
  cv::FileStorage fs;
  try {
    if (!fs.open(name, cv::FileStorage::READ))
      throw InputError(name + ": not an OpenCV FileStorage file (YAML, XML or JSON)");
  } catch (const cv::Exception& e) {
    throw InputError(name + ": not an OpenCV FileStorage file: " + e.err);
  }
  cv::Mat K, dist;
  int width = 0, height = 0;
  double rms = -1;
  std::string source;
  try {
    fs["camera_matrix"] >> K;
    fs["distortion_coefficients"] >> dist;
    fs["image_width"] >> width;
    fs["image_height"] >> height;
    if (!fs["reprojection_error"].empty()) fs["reprojection_error"] >> rms;
    if (!fs["source"].empty()) fs["source"] >> source;
  } catch (const cv::Exception& e) {
    throw InputError(name + ": malformed camera intrinsics: " + e.err);
  }
  if (K.empty() || K.rows != 3 || K.cols != 3)
    throw InputError(name + ": expected a 3x3 'camera_matrix'");
  if (width <= 0 || height <= 0)
    throw InputError(name + ": expected positive 'image_width' and 'image_height'");
  K.convertTo(K, CV_64F);
  CameraIntrinsics k;
  k.image_size = {width, height};
  k.fx = K.at<double>(0, 0);
  k.fy = K.at<double>(1, 1);
  k.cx = K.at<double>(0, 2);
  k.cy = K.at<double>(1, 2);
  if (!dist.empty()) {
    dist.convertTo(dist, CV_64F);
    dist = dist.reshape(1, 1);
    k.distortion.assign(dist.begin<double>(), dist.end<double>());
  }
  k.reprojection_error = rms;
  k.source = source.empty() ? "file " + name : source;
  validate_intrinsics(k, name);
  return k;
}

void write_intrinsics(const std::filesystem::path& path, const CameraIntrinsics& k) {
  validate_intrinsics(k, path.string());
  std::string ext = path.extension().string();
  int format = cv::FileStorage::FORMAT_YAML;
  if (ext == ".json")
    format = cv::FileStorage::FORMAT_JSON;
  else if (ext == ".xml")
    format = cv::FileStorage::FORMAT_XML;
  else if (ext != ".yml" && ext != ".yaml")
    throw InputError(path.string() + ": expected a .yml, .yaml, .xml or .json file name");
  // Written to memory first, then through AtomicFile: never half a file on disk.
  cv::FileStorage fs(ext, cv::FileStorage::WRITE | cv::FileStorage::MEMORY | format);
  fs << "image_width" << k.image_size.width;
  fs << "image_height" << k.image_size.height;
  fs << "camera_matrix" << cv::Mat(k.camera_matrix());
  fs << "distortion_coefficients"
     << cv::Mat(k.distortion.empty() ? std::vector<double>(5, 0.0) : k.distortion, true)
            .reshape(1, 1);
  fs << "reprojection_error" << k.reprojection_error;
  fs << "source" << k.source;
  const std::string text = fs.releaseAndGetString();
  AtomicFile out(path);
  out.write(text);
  out.commit();
}

}  // namespace rostro::calib
