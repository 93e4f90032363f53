#include "calib/actor_calibration.hpp"

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>

#include "calib/fapu_estimation.hpp"
#include "calib/generic_face.hpp"
#include "facecore/error.hpp"

namespace rostro::calib {
namespace {

double median(std::vector<double> v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  if (v.size() % 2 == 1) return *mid;
  return 0.5 * (*mid + *std::max_element(v.begin(), mid));
}

struct Samples {
  std::string marker;
  FeaturePointId fp;
  std::vector<double> x, y;
};

// A frontal first guess for PnP: the prior's face turned to the camera (head frame y up and z
// toward the camera become image y down and camera -z), at the depth where its size matches.
void frontal_guess(const std::vector<cv::Point3d>& object, const std::vector<cv::Point2d>& image,
                   const CameraIntrinsics& k, cv::Vec3d& rvec, cv::Vec3d& tvec) {
  cv::Point3d oc(0, 0, 0);
  cv::Point2d ic(0, 0);
  for (const auto& p : object) oc += p;
  for (const auto& p : image) ic += p;
  oc *= 1.0 / static_cast<double>(object.size());
  ic *= 1.0 / static_cast<double>(image.size());
  double so = 0, si = 0;
  for (std::size_t i = 0; i < object.size(); ++i) {
    so += std::hypot(object[i].x - oc.x, object[i].y - oc.y);
    si += std::hypot(image[i].x - ic.x, image[i].y - ic.y);
  }
  const double depth = si > 0 ? k.fx * so / si : 600.0;
  rvec = {M_PI, 0, 0};
  // Camera position of the object centroid: R * oc + t = depth along the centroid ray.
  const cv::Point3d ray((ic.x - k.cx) / k.fx * depth, (ic.y - k.cy) / k.fy * depth, depth);
  const cv::Point3d rotated(oc.x, -oc.y, -oc.z);
  tvec = {ray.x - rotated.x, ray.y - rotated.y, ray.z - rotated.z};
}

// Reprojection of a prior point under pose (angle-axis relative to facing the camera,
// translation) and a per-axis scale of the prior (x, y; depth takes their mean).
struct ScaledPriorResidual {
  cv::Point3d x;
  cv::Point2d observed;  // normalised, undistorted image coordinates
  template <typename T>
  bool operator()(const T* pose, const T* scale, T* r) const {
    const T depth_scale = (scale[0] + scale[1]) * 0.5;
    const T p[3] = {scale[0] * x.x, -scale[1] * x.y, -depth_scale * x.z};  // F = diag(1,-1,-1)
    T c[3];
    ceres::AngleAxisRotatePoint(pose, p, c);
    r[0] = (c[0] + pose[3]) / (c[2] + pose[5]) - observed.x;
    r[1] = (c[1] + pose[4]) / (c[2] + pose[5]) - observed.y;
    return true;
  }
};

// Keeps the neutral head near facing the camera: a y-squashed face and a pitched one look
// alike in one frontal image, so the calibration assumes the actor faces the camera.
struct FacingPrior {
  double weight;
  template <typename T>
  bool operator()(const T* pose, T* r) const {
    for (int i = 0; i < 3; ++i) r[i] = weight * pose[i];
    return true;
  }
};

}  // namespace

std::map<std::string, Eigen::Vector3d> place_nominal_markers(
    const std::vector<NominalMarker>& markers, const FeaturePointPositions& prior) {
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> pairs;  // nominal, prior
  for (const auto& m : markers)
    if (m.feature_point)
      if (auto it = prior.find(*m.feature_point); it != prior.end())
        pairs.emplace_back(m.position, it->second);
  if (pairs.size() < 2)
    throw InputError(
        "marker layout: fewer than two markers sit on feature points the face "
        "prior knows, so the layout cannot be placed on it");
  Eigen::Vector3d nc = Eigen::Vector3d::Zero(), pc = Eigen::Vector3d::Zero();
  for (const auto& [n, p] : pairs) nc += n, pc += p;
  nc /= static_cast<double>(pairs.size());
  pc /= static_cast<double>(pairs.size());
  double num = 0, den = 0;
  for (const auto& [n, p] : pairs) {
    num += (n - nc).dot(p - pc);
    den += (n - nc).squaredNorm();
  }
  const double scale = den > 0 ? num / den : 1.0;
  std::map<std::string, Eigen::Vector3d> out;
  for (const auto& m : markers) out[m.id] = pc + scale * (m.position - nc);
  return out;
}

ActorProfile calibrate_actor(const std::vector<tracking::TrackedFrame>& frames,
                             const CameraIntrinsics& camera,
                             const ActorCalibrationOptions& options) {
  if (frames.empty()) throw InputError("actor calibration: no neutral frames given");
  validate_intrinsics(camera, "actor calibration camera");
  const FeaturePointPositions& prior = options.prior ? *options.prior : generic_face_points();

  std::vector<Samples> samples;
  for (const auto& frame : frames)
    for (const auto& m : frame.markers) {
      auto it = std::find_if(samples.begin(), samples.end(),
                             [&](const Samples& s) { return s.marker == m.marker; });
      if (it == samples.end())
        it = samples.insert(samples.end(), {m.marker, m.feature_point, {}, {}});
      if (!m.valid || !std::isfinite(m.position.x) || !std::isfinite(m.position.y)) continue;
      it->x.push_back(m.position.x);
      it->y.push_back(m.position.y);
    }

  ActorProfile profile;
  profile.name = options.name;
  profile.camera = camera;
  profile.neutral_frames = static_cast<int>(frames.size());
  const double needed = options.min_valid_fraction * static_cast<double>(frames.size());
  for (const Samples& s : samples) {
    if (s.x.empty() || static_cast<double>(s.x.size()) < needed) {
      profile.fapu_notes["left out: " + s.marker] = "valid in " + std::to_string(s.x.size()) +
                                                    " of " + std::to_string(frames.size()) +
                                                    " neutral frames";
      continue;
    }
    NeutralMarker m;
    m.marker = s.marker;
    m.feature_point = s.fp;
    m.rigid = options.rigid_markers.count(s.marker) != 0 || !is_feature_point(s.fp);
    m.image = {median(s.x), median(s.y)};
    m.frames_seen = static_cast<int>(s.x.size());
    if (auto b = options.beside.find(m.marker); b != options.beside.end() && !m.rigid)
      profile.marker_motion[m.marker] = b->second.motion;
    else if (options.motion && !m.rigid)
      if (auto it = options.motion->find(m.feature_point); it != options.motion->end())
        profile.marker_motion[m.marker] = it->second;
    profile.markers.push_back(std::move(m));
  }
  if (profile.markers.size() < 4)
    throw InputError("actor calibration: only " + std::to_string(profile.markers.size()) +
                     " markers are valid in enough neutral frames; at least 4 are needed");

  // Undistorted, normalised image coordinates of the neutral markers.
  std::vector<cv::Point2d> pixels, normalised;
  for (const auto& m : profile.markers) pixels.push_back(m.image);
  cv::undistortPoints(
      pixels, normalised, cv::Mat(camera.camera_matrix()),
      cv::Mat(camera.distortion.empty() ? std::vector<double>{} : camera.distortion));

  // FAPU on the image (px, y up), for seed2d.
  FeaturePointPositions image_points;
  for (const auto& m : profile.markers)
    if (is_feature_point(m.feature_point))
      image_points[m.feature_point] = Eigen::Vector3d(m.image.x, -m.image.y, 0);
  profile.fapu_image = estimate_fapu(image_points, prior, options.lid_markers_on_margin).fapu;

  // Head pose from the prior, then the 3D shape at the prior's depths.
  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> image;
  std::vector<std::size_t> with_prior;
  std::vector<Eigen::Vector3d> from_point;  // a dot's place less its feature point's (prior)
  for (std::size_t i = 0; i < profile.markers.size(); ++i) {
    const NeutralMarker& m = profile.markers[i];
    Eigen::Vector3d x, offset = Eigen::Vector3d::Zero();
    const auto point = prior.find(m.feature_point);
    if (auto own = options.marker_priors.find(m.marker);
        own != options.marker_priors.end() && point == prior.end())
      x = own->second;
    else if (auto b = options.beside.find(m.marker);
             b != options.beside.end() && point != prior.end())
      x = b->second.position, offset = x - point->second;
    else if (point != prior.end())
      x = point->second;
    else
      continue;
    object.emplace_back(x.x(), x.y(), x.z());
    image.push_back(pixels[i]);
    with_prior.push_back(i);
    from_point.push_back(offset);
  }
  if (object.size() < 4)
    throw InputError("actor calibration: only " + std::to_string(object.size()) +
                     " markers sit on feature points the face prior knows; at least 4 are needed");
  cv::Vec3d rvec, tvec;
  frontal_guess(object, image, camera, rvec, tvec);
  // Pose plus a per-axis scale of the prior, so the actor's proportions are not read as a tilt.
  double pose[6] = {0, 0, 0, tvec[0], tvec[1], tvec[2]};
  double scale[2] = {1, 1};
  {
    ceres::Problem problem;
    for (std::size_t n = 0; n < object.size(); ++n)
      problem.AddResidualBlock(new ceres::AutoDiffCostFunction<ScaledPriorResidual, 2, 6, 2>(
                                   new ScaledPriorResidual{object[n], normalised[with_prior[n]]}),
                               new ceres::HuberLoss(2.0 / camera.fx), pose, scale);
    // Weight: a 1 degree tilt costs as much as a 1 px error of a third of the markers.
    const double weight =
        options.facing_prior * std::sqrt(static_cast<double>(object.size()) / 3.0) / camera.fx;
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<FacingPrior, 3, 6>(
                                 new FacingPrior{weight / (M_PI / 180.0)}),
                             nullptr, pose);
    problem.SetParameterLowerBound(scale, 0, 0.5);
    problem.SetParameterLowerBound(scale, 1, 0.5);
    problem.SetParameterUpperBound(scale, 0, 2.0);
    problem.SetParameterUpperBound(scale, 1, 2.0);
    ceres::Solver::Options so;
    so.linear_solver_type = ceres::DENSE_QR;
    so.logging_type = ceres::SILENT;
    so.max_num_iterations = 100;
    ceres::Solver::Summary summary;
    ceres::Solve(so, &problem, &summary);
    if (!summary.IsSolutionUsable())
      throw InputError("actor calibration: the neutral head pose fit failed: " +
                       summary.BriefReport());
  }
  cv::Matx33d R;
  cv::Rodrigues(cv::Vec3d(pose[0], pose[1], pose[2]), R);
  R = R * cv::Matx33d(1, 0, 0, 0, -1, 0, 0, 0, -1);
  cv::Rodrigues(R, rvec);
  tvec = {pose[3], pose[4], pose[5]};
  profile.neutral_pose = tracking::HeadPose{rvec, tvec};
  const double sz = (scale[0] + scale[1]) / 2;
  for (auto& o : object) o = {o.x * scale[0], o.y * scale[1], o.z * sz};

  FeaturePointPositions shape;
  for (std::size_t n = 0; n < with_prior.size(); ++n) {
    const std::size_t i = with_prior[n];
    const cv::Vec3d in_camera = R * cv::Vec3d(object[n].x, object[n].y, object[n].z) + tvec;
    const double depth = in_camera[2];
    const cv::Vec3d ray(normalised[i].x * depth, normalised[i].y * depth, depth);
    const cv::Vec3d head = R.t() * (ray - tvec);
    profile.markers[i].position = Eigen::Vector3d(head[0], head[1], head[2]);
    const Eigen::Vector3d offset =
        from_point[n].cwiseProduct(Eigen::Vector3d(scale[0], scale[1], sz));
    if (is_feature_point(profile.markers[i].feature_point))
      shape[profile.markers[i].feature_point] = *profile.markers[i].position - offset;
  }
  FapuEstimate estimate = estimate_fapu(shape, prior, options.lid_markers_on_margin);
  profile.fapu = estimate.fapu;
  for (auto& [key, note] : estimate.notes) profile.fapu_notes[key] = note;
  profile.shape_source = options.prior_name +
                         ", scaled to the actor per axis: depth of each marker from the prior, x "
                         "and y from the neutral image (the actor assumed to face the camera)";
  return profile;
}

ActorProfile recalibrate_focal(const ActorProfile& profile, double focal_px) {
  CameraIntrinsics camera = profile.camera;
  camera.fx = camera.fy = focal_px;
  tracking::TrackedFrame neutral;
  // The generic face fills the points no marker carries (the FAPU estimation asks for them);
  // the FAPU themselves are kept from the first calibration below.
  FeaturePointPositions shape = generic_face_points();
  ActorCalibrationOptions o;
  o.name = profile.name;
  o.prior = &shape;
  o.prior_name = "the profile's own shape";
  for (const NeutralMarker& m : profile.markers) {
    neutral.markers.push_back({m.marker, m.feature_point, m.image, true, 1.0});
    if (m.rigid) o.rigid_markers.insert(m.marker);
    if (!m.position) continue;
    if (is_feature_point(m.feature_point))
      shape[m.feature_point] = *m.position;
    else
      o.marker_priors[m.marker] = *m.position;
  }
  ActorProfile out = calibrate_actor({neutral}, camera, o);
  out.fapu = profile.fapu;
  out.fapu_notes = profile.fapu_notes;
  out.fapu_image = profile.fapu_image;
  out.fap_gains = profile.fap_gains;
  out.marker_motion = profile.marker_motion;
  out.neutral_frames = profile.neutral_frames;
  for (NeutralMarker& m : out.markers)
    if (const NeutralMarker* old = profile.find_marker(m.marker)) m.frames_seen = old->frames_seen;
  out.shape_source = profile.shape_source + "; redone at f = " + std::to_string(focal_px) +
                     " px (focal length refined from head turns)";
  return out;
}

}  // namespace rostro::calib
