#pragma once
// Synthetic marker observations for the calib and mapping tests: a known actor face (3D
// feature points in mm), moved by known FAP values along fap_axis() x the actor's FAPU,
// posed by a known head rotation and translation, projected through a pinhole camera, plus
// Gaussian noise. Header-only so tests/calib can use it too.

#include <cmath>
#include <map>
#include <opencv2/calib3d.hpp>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "calib/actor_calibration.hpp"
#include "calib/actor_profile.hpp"
#include "calib/camera_intrinsics.hpp"
#include "calib/generic_face.hpp"
#include "facecore/fap_table.hpp"
#include "facecore/fapu.hpp"
#include "tracking/tracked_frame.hpp"

namespace rostro::test {

// The dots of data/layouts/default.json plus its three headband tags (no feature point).
inline std::vector<std::pair<std::string, FeaturePointId>> default_markers() {
  return {{"tag36h11:0", {}},      {"tag36h11:1", {}},     {"tag36h11:2", {}},
          {"brow_l_in", {4, 1}},   {"brow_r_in", {4, 2}},  {"brow_l_mid", {4, 3}},
          {"brow_r_mid", {4, 4}},  {"brow_l_out", {4, 5}}, {"brow_r_out", {4, 6}},
          {"lid_l_up", {3, 1}},    {"lid_r_up", {3, 2}},   {"lid_l_low", {3, 3}},
          {"lid_r_low", {3, 4}},   {"eye_l_out", {3, 7}},  {"eye_l_in", {3, 11}},
          {"eye_r_in", {3, 8}},    {"eye_r_out", {3, 12}}, {"cheekbone_l", {5, 3}},
          {"cheekbone_r", {5, 4}}, {"cheek_l", {5, 1}},    {"cheek_r", {5, 2}},
          {"nose_l", {9, 1}},      {"nose_r", {9, 2}},     {"nose_tip", {9, 3}},
          {"lip_top", {8, 1}},     {"lip_bot", {8, 2}},    {"mouth_l", {8, 3}},
          {"mouth_r", {8, 4}},     {"lip_top_l", {8, 5}},  {"lip_top_r", {8, 6}},
          {"lip_bot_l", {8, 7}},   {"lip_bot_r", {8, 8}},  {"chin_boss", {2, 10}},
          {"chin", {2, 1}}};
}

// Where the headband tags sit on the generic face (the layout's places moved to its origin).
inline std::map<std::string, Eigen::Vector3d> generic_tag_positions() {
  return {
      {"tag36h11:0", {0, 53, 10}}, {"tag36h11:1", {-42, 47, -10}}, {"tag36h11:2", {42, 47, -10}}};
}

struct SyntheticActor {
  FeaturePointPositions shape;  // true neutral face, head frame, mm
  Fapu fapu;                    // true FAPU of that face
  std::vector<std::pair<std::string, FeaturePointId>> markers = default_markers();
  std::map<std::string, Eigen::Vector3d> tags;  // true positions of the markers on no point
  calib::CameraIntrinsics camera;

  Eigen::Vector3d neutral(const std::string& id, FeaturePointId fp) const {
    return is_feature_point(fp) ? shape.at(fp) : tags.at(id);
  }
};

// The generic face stretched by (sx, sy, sz): an actor whose proportions differ from the prior.
inline SyntheticActor make_actor(double sx = 1.04, double sy = 0.97, double sz = 1.0) {
  SyntheticActor a;
  for (const auto& [id, p] : calib::generic_face_points())
    a.shape[id] = Eigen::Vector3d(p.x() * sx, p.y() * sy, p.z() * sz);
  a.fapu = fapu_from_feature_points(a.shape);
  for (const auto& [id, p] : generic_tag_positions())
    a.tags[id] = Eigen::Vector3d(p.x() * sx, p.y() * sy, p.z() * sz);
  a.camera.image_size = {1280, 720};
  a.camera.fx = a.camera.fy = 1000;
  a.camera.cx = 640;
  a.camera.cy = 360;
  a.camera.source = "synthetic";
  return a;
}

inline double deg(double d) {
  return d * M_PI / 180.0;
}

// Head frame -> camera pose for a head turned by yaw (toward its left), pitch (down) and
// roll (toward its right) from facing the camera, its origin at `t` (mm, camera frame).
inline tracking::HeadPose head_pose(double yaw_deg, double pitch_deg, double roll_deg,
                                    cv::Vec3d t = {10, -20, 600}) {
  const double y = deg(yaw_deg), p = deg(pitch_deg), r = deg(roll_deg);
  const cv::Matx33d ry(std::cos(y), 0, std::sin(y), 0, 1, 0, -std::sin(y), 0, std::cos(y));
  const cv::Matx33d rx(1, 0, 0, 0, std::cos(p), -std::sin(p), 0, std::sin(p), std::cos(p));
  const cv::Matx33d rz(std::cos(r), -std::sin(r), 0, std::sin(r), std::cos(r), 0, 0, 0, 1);
  const cv::Matx33d frontal(1, 0, 0, 0, -1, 0, 0, 0, -1);
  cv::Vec3d rv;
  cv::Rodrigues(frontal * ry * rx * rz, rv);
  return {rv, t};
}

// Where feature point `fp` of the actor is with these FAP values (head frame, mm).
inline Eigen::Vector3d moved_point(const SyntheticActor& a, const std::string& marker,
                                   FeaturePointId fp, const std::map<int, double>& faps) {
  Eigen::Vector3d x = a.neutral(marker, fp);
  if (!is_feature_point(fp)) return x;
  for (const auto& [id, value] : faps) {
    const FapInfo& info = fap_info(id);
    if (info.feature_point != fp.str()) continue;
    const auto axis = fap_axis(info);
    x += value * a.fapu.unit_size(info.unit) * Eigen::Vector3d(axis[0], axis[1], axis[2]);
  }
  return x;
}

inline tracking::TrackedFrame render(const SyntheticActor& a, const std::map<int, double>& faps,
                                     const tracking::HeadPose& pose, double noise_px,
                                     std::mt19937& rng, long index = 0) {
  std::normal_distribution<double> noise(0.0, noise_px > 0 ? noise_px : 1.0);
  cv::Matx33d R;
  cv::Rodrigues(pose.rotation, R);
  tracking::TrackedFrame f;
  f.frame = index;
  f.time_s = static_cast<double>(index) / 25.0;
  for (const auto& [id, fp] : a.markers) {
    const Eigen::Vector3d x = moved_point(a, id, fp, faps);
    const cv::Vec3d c = R * cv::Vec3d(x.x(), x.y(), x.z()) + pose.translation;
    cv::Point2d px(a.camera.fx * c[0] / c[2] + a.camera.cx,
                   a.camera.fy * c[1] / c[2] + a.camera.cy);
    if (noise_px > 0) px += cv::Point2d(noise(rng), noise(rng));
    f.markers.push_back({id, fp, px, true, 1.0});
  }
  return f;
}

// A take of `a`: `neutral` still frames, then the jaw opening by 40 MNS a frame for `moving`
// frames, with `noise_px` of marker noise: each frame's FAPs differ (a frame can be told apart
// by its open_jaw), and a fit's warm start carries from frame to frame.
inline std::vector<tracking::TrackedFrame> jaw_opening_take(const SyntheticActor& a, long neutral,
                                                            long moving,
                                                            const tracking::HeadPose& pose,
                                                            unsigned seed, double noise_px = 0.1) {
  constexpr int kOpenJaw = 3;
  std::mt19937 rng(seed);
  std::vector<tracking::TrackedFrame> frames;
  for (long i = 0; i < neutral + moving; ++i) {
    const double jaw = i < neutral ? 0.0 : 40.0 * static_cast<double>(i - neutral + 1);
    frames.push_back(render(a, {{kOpenJaw, jaw}}, pose, noise_px, rng, i));
  }
  return frames;
}

// The profile a perfect calibration would give: true 3D shape, true FAPU, true neutral pose.
inline calib::ActorProfile exact_profile(const SyntheticActor& a,
                                         const tracking::HeadPose& neutral) {
  calib::ActorProfile p;
  p.name = "synthetic";
  p.fapu = a.fapu;
  p.camera = a.camera;
  p.neutral_pose = neutral;
  std::mt19937 rng(1);
  const auto frame = render(a, {}, neutral, 0, rng);
  for (std::size_t i = 0; i < a.markers.size(); ++i) {
    calib::NeutralMarker m;
    m.marker = a.markers[i].first;
    m.feature_point = a.markers[i].second;
    m.image = frame.markers[i].position;
    m.position = a.neutral(m.marker, m.feature_point);
    m.rigid = !is_feature_point(m.feature_point);
    m.frames_seen = 1;
    p.markers.push_back(m);
  }
  p.fapu_image = p.fapu;  // not used by the Ceres fit
  return p;
}

// Calibration options for the synthetic actor: the tags' places on the generic face.
inline calib::ActorCalibrationOptions calibration_options() {
  calib::ActorCalibrationOptions o;
  o.marker_priors = generic_tag_positions();
  return o;
}

// A lively test expression touching every FAP the default markers carry.
inline std::map<int, double> test_expression(double scale = 1.0) {
  std::map<int, double> f = {{3, 320},  {15, -40}, {18, 60},  {19, 300}, {20, 280}, {21, 90},
                             {22, 80},  {39, 50},  {40, 45},  {41, 70},  {42, 60},  {31, 90},
                             {32, 70},  {33, 110}, {34, 95},  {35, 60},  {36, 55},  {37, 30},
                             {38, 25},  {51, -60}, {52, -90}, {53, 140}, {54, 120}, {55, -45},
                             {56, -50}, {57, -70}, {58, -65}, {59, 110}, {60, 95},  {61, 40},
                             {62, 35},  {63, 20},  {64, -15}};
  for (auto& [id, v] : f) {
    v *= scale;
    if (!fap_info(id).bidirectional && v < 0) v = 0;  // unidirectional FAPs are never negative
  }
  return f;
}

}  // namespace rostro::test
