#include "render/camera.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <vector>

#include "facecore/error.hpp"

namespace rostro::render {
namespace {

double radians(double deg) {
  return deg * std::numbers::pi / 180.0;
}

std::string trim(std::string_view s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string_view::npos) return {};
  const auto e = s.find_last_not_of(" \t");
  return std::string(s.substr(b, e - b + 1));
}

[[noreturn]] void bad_camera(std::string_view text) {
  throw InputError("camera '" + std::string(text) +
                   "': expected front, three-quarter, or yaw,pitch,roll[,distance[,fov]] "
                   "in degrees");
}

}  // namespace

CameraPose CameraPose::front() {
  return CameraPose{};
}

CameraPose CameraPose::three_quarter() {
  CameraPose pose;
  pose.yaw_deg = 35.0;
  pose.pitch_deg = 5.0;
  return pose;
}

CameraPose parse_camera(std::string_view text) {
  const std::string t = trim(text);
  if (t == "front") return CameraPose::front();
  if (t == "three-quarter" || t == "three_quarter" || t == "3/4") {
    return CameraPose::three_quarter();
  }
  std::vector<double> numbers;
  std::stringstream in(t);
  std::string item;
  while (std::getline(in, item, ',')) {
    const std::string v = trim(item);
    std::size_t used = 0;
    double x = 0.0;
    try {
      x = std::stod(v, &used);
    } catch (const std::exception&) {
      bad_camera(text);
    }
    if (used != v.size() || !std::isfinite(x)) bad_camera(text);
    numbers.push_back(x);
  }
  if (numbers.size() < 3 || numbers.size() > 5) bad_camera(text);
  CameraPose pose;
  pose.yaw_deg = numbers[0];
  pose.pitch_deg = numbers[1];
  pose.roll_deg = numbers[2];
  if (numbers.size() > 3) {
    if (numbers[3] < 0.0) bad_camera(text);
    pose.distance = numbers[3];
  }
  if (numbers.size() > 4) {
    if (numbers[4] <= 1.0 || numbers[4] >= 170.0) bad_camera(text);
    pose.fov_deg = numbers[4];
  }
  return pose;
}

std::string describe(const CameraPose& pose) {
  std::ostringstream out;
  out << "yaw " << pose.yaw_deg << ", pitch " << pose.pitch_deg << ", roll " << pose.roll_deg
      << ", fov " << pose.fov_deg;
  if (pose.distance > 0.0) out << ", distance " << pose.distance;
  return out.str();
}

CameraMatrices frame_camera(const CameraPose& pose, const Bounds& frame, double aspect) {
  using Eigen::Vector3d;
  const Eigen::Matrix3d rotation = (Eigen::AngleAxisd(radians(pose.yaw_deg), Vector3d::UnitY()) *
                                    Eigen::AngleAxisd(radians(-pose.pitch_deg), Vector3d::UnitX()) *
                                    Eigen::AngleAxisd(radians(pose.roll_deg), Vector3d::UnitZ()))
                                       .toRotationMatrix();
  const auto c = frame.center();
  const Vector3d center(c[0], c[1], c[2]);
  const auto s = frame.size();
  const Vector3d half(s[0] / 2, s[1] / 2, s[2] / 2);
  const double radius = std::max(half.norm(), 1e-6);

  const double tan_v = std::tan(radians(pose.fov_deg) / 2.0);
  const double tan_h = tan_v * std::max(aspect, 1e-6);
  double distance = pose.distance;
  if (distance <= 0.0) {
    // The smallest distance at which every corner of the box, seen from this direction,
    // falls inside the (margin-shrunk) view: |x| <= (D - z) tan(h/2) / margin, same for y.
    distance = 0.0;
    for (int corner = 0; corner < 8; ++corner) {
      const Vector3d offset((corner & 1) ? half.x() : -half.x(),
                            (corner & 2) ? half.y() : -half.y(),
                            (corner & 4) ? half.z() : -half.z());
      const Vector3d p = rotation.transpose() * offset;
      distance = std::max(distance, p.z() + pose.margin * std::abs(p.x()) / tan_h);
      distance = std::max(distance, p.z() + pose.margin * std::abs(p.y()) / tan_v);
    }
    distance = std::max(distance, radius * 1.05);
  }

  CameraMatrices m;
  m.distance = distance;
  const Vector3d eye = center + rotation * Vector3d(0.0, 0.0, distance);
  m.eye = eye.cast<float>();

  Eigen::Matrix4d world_from_camera = Eigen::Matrix4d::Identity();
  world_from_camera.topLeftCorner<3, 3>() = rotation;
  world_from_camera.topRightCorner<3, 1>() = eye;
  m.view = world_from_camera.inverse().cast<float>();

  const double near_plane = std::max(distance - 2.0 * radius, distance * 0.01);
  const double far_plane = distance + 2.0 * radius;
  Eigen::Matrix4d proj = Eigen::Matrix4d::Zero();
  proj(0, 0) = 1.0 / tan_h;
  proj(1, 1) = 1.0 / tan_v;
  proj(2, 2) = -(far_plane + near_plane) / (far_plane - near_plane);
  proj(2, 3) = -2.0 * far_plane * near_plane / (far_plane - near_plane);
  proj(3, 2) = -1.0;
  m.projection = proj.cast<float>();
  return m;
}

bool PixelProjector::project(const Eigen::Vector3f& p, cv::Point2d& out) const {
  const Eigen::Vector4f c = m.view * Eigen::Vector4f(p.x(), p.y(), p.z(), 1.0f);
  if (c.z() >= 0) return false;
  const double x_ndc = m.projection(0, 0) * c.x() / -c.z();
  const double y_ndc = m.projection(1, 1) * c.y() / -c.z();
  out = {(x_ndc + 1.0) * width / 2.0 - 0.5, (1.0 - y_ndc) * height / 2.0 - 0.5};
  return true;
}

}  // namespace rostro::render
