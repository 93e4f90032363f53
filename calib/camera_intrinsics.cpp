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

CameraIntrinsics intrinsics_for_frames(const CameraIntrinsics& k, cv::Size frame_size,
                                       const std::string& what, std::string* note) {
  if (k.image_size == frame_size || frame_size.empty()) return k;
  auto size_text = [](cv::Size s) {
    return std::to_string(s.width) + "x" + std::to_string(s.height);
  };
  const double sx = static_cast<double>(frame_size.width) / k.image_size.width;
  const double sy = static_cast<double>(frame_size.height) / k.image_size.height;
  if (std::abs(sx / sy - 1.0) > 0.01)
    throw InputError(what + ": calibrated on " + size_text(k.image_size) +
                     " images, but the frames are " + size_text(frame_size) +
                     " (another aspect ratio: a crop or another camera mode); calibrate at " +
                     size_text(frame_size));
  CameraIntrinsics scaled = k;
  scaled.image_size = frame_size;
  scaled.fx *= sx;
  scaled.fy *= sy;
  // Pixel centres sit at integers: a resize maps x to (x + 0.5) s - 0.5.
  scaled.cx = (k.cx + 0.5) * sx - 0.5;
  scaled.cy = (k.cy + 0.5) * sy - 0.5;
  scaled.source = k.source + ", scaled from " + size_text(k.image_size);
  if (note)
    *note = what + ": calibrated on " + size_text(k.image_size) + " images, scaled to the " +
            size_text(frame_size) + " frames";
  return scaled;
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

namespace {

// `input` is a path, or the text itself with cv::FileStorage::MEMORY in `flags`.
CameraIntrinsics read_storage(const std::string& input, int flags, const std::string& name) {
  cv::FileStorage fs;
  try {
    if (!fs.open(input, cv::FileStorage::READ | flags))
      throw InputError(name + ": not an OpenCV FileStorage file (YAML, XML or JSON)");
  } catch (const cv::Exception& e) {
    throw InputError(name + ": not an OpenCV FileStorage file: " + e.err);
  } catch (const std::exception& e) {
    // OpenCV's parser lets a damaged file end in std::length_error (found by fuzz_intrinsics).
    throw InputError(name + ": not an OpenCV FileStorage file: " + e.what());
  }
  cv::Mat K, dist;
  int width = 0, height = 0;
  double rms = -1;
  std::string source;
  // A matrix's declared size is checked before OpenCV allocates it: a damaged 'cols' would
  // otherwise ask for gigabytes (found by fuzz_intrinsics).
  const auto check_size = [&](const char* key, long max_values) {
    const cv::FileNode node = fs[key];
    if (!node.isMap()) return;  // reading it below reports what is wrong
    const long rows = static_cast<int>(node["rows"]), cols = static_cast<int>(node["cols"]);
    if (rows < 0 || cols < 0 || rows * cols > max_values)
      throw InputError(name + ": '" + key + "' declares " + std::to_string(rows) + "x" +
                       std::to_string(cols) + " values, expected at most " +
                       std::to_string(max_values));
  };
  try {
    check_size("camera_matrix", 9);
    check_size("distortion_coefficients", 14);
    fs["camera_matrix"] >> K;
    fs["distortion_coefficients"] >> dist;
    fs["image_width"] >> width;
    fs["image_height"] >> height;
    if (!fs["reprojection_error"].empty()) fs["reprojection_error"] >> rms;
    if (!fs["source"].empty()) fs["source"] >> source;
  } catch (const cv::Exception& e) {
    throw InputError(name + ": malformed camera intrinsics: " + e.err);
  } catch (const std::exception& e) {
    throw InputError(name + ": malformed camera intrinsics: " + e.what());
  }
  if (K.empty() || K.rows != 3 || K.cols != 3 || K.channels() != 1)
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

}  // namespace

CameraIntrinsics read_intrinsics(const std::filesystem::path& path) {
  const std::string name = path.string();
  if (!std::filesystem::exists(path)) throw InputError(name + ": camera intrinsics file not found");
  return read_storage(name, 0, name);
}

CameraIntrinsics parse_intrinsics(const std::string& text, const std::string& name) {
  if (text.empty()) throw InputError(name + ": empty camera intrinsics");
  return read_storage(text, cv::FileStorage::MEMORY, name);
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
