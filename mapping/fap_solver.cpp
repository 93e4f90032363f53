#include "mapping/fap_solver.hpp"

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <unordered_map>
#include <vector>

#include "facecore/error.hpp"
#include "facecore/fap_table.hpp"
#include "facecore/named_options.hpp"
#include "facecore/option_check.hpp"
#include "mapping/hierarchy.hpp"
#include "mapping/marker_residual.hpp"

namespace rostro::mapping {
namespace {

using internal::Intrinsics;
using internal::MarkerResidual;
using internal::Observation;

// The fit's rotation is taken relative to a camera-facing head: X_cam = R(aa) F X_head + t,
// F = diag(1, -1, -1) (head y up / z out -> image y down / toward the camera), so a frontal
// head is aa = 0, far from the angle-axis singularity at 180 degrees.
cv::Matx33d flip() {
  return {1, 0, 0, 0, -1, 0, 0, 0, -1};
}

// gain_i * weight_i * (value_i - target_i) over a run of the parameter block starting at
// column `first`: the weak pull of the FAPs toward the previous frame (first = 6), and of the
// pose toward its constant-velocity prediction (first = 0).
class PriorResiduals : public ceres::CostFunction {
 public:
  PriorResiduals(const std::vector<double>* targets, const std::vector<double>* gains,
                 std::vector<double> weights, int parameters, std::size_t first)
      : targets_(targets), gains_(gains), weights_(std::move(weights)), first_(first) {
    set_num_residuals(static_cast<int>(weights_.size()));
    mutable_parameter_block_sizes()->push_back(parameters);
  }
  bool Evaluate(double const* const* values, double* residuals, double** jacobians) const override {
    const std::size_t n = weights_.size();
    const auto cols = static_cast<std::size_t>(parameter_block_sizes()[0]);
    for (std::size_t i = 0; i < n; ++i)
      residuals[i] = (*gains_)[i] * weights_[i] * (values[0][first_ + i] - (*targets_)[i]);
    if (jacobians && jacobians[0]) {
      std::fill(jacobians[0], jacobians[0] + n * cols, 0.0);
      for (std::size_t i = 0; i < n; ++i)
        jacobians[0][i * cols + first_ + i] = (*gains_)[i] * weights_[i];
    }
    return true;
  }

 private:
  const std::vector<double>* targets_;
  const std::vector<double>* gains_;
  std::vector<double> weights_;
  std::size_t first_;
};

// How hard a clamped unidirectional FAP is pinned to its bound (or a held FAP to its previous
// value): a move of its marker by p pixels costs as a reprojection error of kHoldWeight x p.
// Fixed, not a multiple of the weak prior, so weakening the prior leaves the pins as firm.
constexpr double kHoldWeight = 50.0;
// A marker measures a FAP when the FAP moves it at least this share as far as the marker it
// moves most. The default head's upper-lid region reaches the inner eye corner (a quarter of
// the lid's motion): with the lid dot lost (merged with the pupil as the lid lowers in a
// smile) the corner alone set close_t_eyelid, and a tenth of a pixel of the corner's error
// was 20-30 IRISD (closed loop, Xface joy at 640x480: 7.6-8.7 % of range). Such a FAP is left
// to the hierarchy's mirror when its left/right twin is measured and within kTwinAgreementPx
// of it (moving the FAP's own point), and reported as fitted otherwise: one eye closing alone
// (a wink, a blink's lids lost while merged) is far from its twin, and the corner then reads
// it well enough (range of motion: close_t_eyelid 0.4-0.7 % of a 498 IRISD range).
constexpr double kMeasuringShare = 0.5;
constexpr double kTwinAgreementPx = 1.0;

}  // namespace

std::array<double, 3> head_rotation_faps(const tracking::HeadPose& neutral,
                                         const tracking::HeadPose& pose) {
  cv::Matx33d rn, r;
  cv::Rodrigues(neutral.rotation, rn);
  cv::Rodrigues(pose.rotation, r);
  const cv::Matx33d h = rn.t() * r;  // rotation in the head's own frame
  const double pitch = std::asin(std::clamp(-h(1, 2), -1.0, 1.0));
  const double roll = std::atan2(h(1, 0), h(1, 1));
  const double yaw = std::atan2(h(0, 2), h(2, 2));
  return {pitch / kAngleUnitRad, yaw / kAngleUnitRad, roll / kAngleUnitRad};
}

struct FapSolver::Impl {
  calib::ActorProfile profile;  // a copy: the solver outlives the caller's profile
  SolverOptions options;
  MarkerModel model;
  Intrinsics k{};
  std::unordered_map<std::string, std::size_t> marker_index;
  std::vector<Observation> observations;
  std::vector<int> fap_slot;  // FAP id -> index among the fitted FAPs, -1 when not fitted
  // The one parameter block: angle-axis (3), translation (3), then the fitted FAPs.
  std::vector<double> x;
  std::vector<double> previous;  // FAP values of the previous frame (the prior's targets)
  // The pose prior's targets (the previous pose plus the smoothed velocity) and gains (0 on a
  // cold start).
  std::vector<double> pose_target, pose_gain;
  // Fitted FAP -> the markers that measure it: those it moves at least kMeasuringShare as far as
  // the marker it moves most (its own feature point's).
  std::vector<std::vector<std::size_t>> measured_by;
  // Fitted FAP -> the markers that read it at all (SolverOptions::min_reading_share).
  std::vector<std::vector<std::size_t>> read_by;
  std::vector<double> px_per_unit;  // per fitted FAP: pixels per unit at its most moved marker
  double neutral_pose[6] = {0, 0, 0, 0, 0, 0};
  double last_pose[6] = {0, 0, 0, 0, 0, 0};      // pose of the frame before the previous one
  double pose_velocity[6] = {0, 0, 0, 0, 0, 0};  // per frame, smoothed (pose prior)
  tracking::HeadPose neutral_cv;
  std::unique_ptr<ceres::LossFunction> loss;
  std::unique_ptr<ceres::LossFunction> pose_loss;  // the pose prior's (pose_prior_scale_px)
  std::vector<std::unique_ptr<ceres::CostFunction>> costs;
  ceres::Problem problem;
  ceres::Solver::Options solver;
  int fitted_in_a_row = 0;  // consecutive fitted frames: 0 = cold start, 2+ = a velocity
  // Focal length refinement (SolverOptions::refine_default_focal): the calibrated focal
  // length times exp(log_focal), and the information gathered about log_focal so far.
  bool refine_focal = false;
  double base_fx = 0, base_fy = 0, log_focal = 0, focal_information = 0;
  std::vector<Eigen::Vector3d> shape_rate;  // per marker, see set_shape_rates()
  // Per fitted FAP: 1, or hold_gain for a unidirectional FAP clamped at its bound in this frame
  // or a FAP held at its previous value (SolverOptions::hold_while_hidden).
  std::vector<double> prior_gain;
  std::vector<double> hold_gain;  // kHoldWeight / the FAP's prior weight
  std::vector<bool> clamped;      // unidirectional FAPs pinned to their bound (the active set)
  std::vector<bool> bounded;      // unidirectional and not in SolverOptions::signed_faps
  std::vector<double> bound;  // where a bounded FAP is clamped: 0, or SolverOptions::lower_bounds
  // Per hold rule: the markers on its feature point, and the fitted FAPs it holds.
  std::vector<std::pair<std::vector<std::size_t>, std::vector<std::size_t>>> holds;

  static ceres::Problem::Options problem_options() {
    ceres::Problem::Options o;
    o.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    o.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    return o;
  }

  std::size_t fap_count() const { return model.faps.size(); }
  double* pose() { return x.data(); }
  double* values() { return x.data() + 6; }

  Impl(const calib::ActorProfile& p, const SolverOptions& o)
      : profile(p), options(o), model(build_marker_model(p, o.model)), problem(problem_options()) {
    const auto& cam = p.camera;
    k = {cam.fx, cam.fy, cam.cx, cam.cy};
    base_fx = cam.fx;
    base_fy = cam.fy;
    refine_focal = o.refine_default_focal && calib::is_default_intrinsics(cam);
    focal_information = 1.0 / (o.focal_prior_sigma * o.focal_prior_sigma);
    observations.resize(model.markers.size());
    for (std::size_t i = 0; i < model.markers.size(); ++i)
      marker_index[model.markers[i].marker] = i;
    fap_slot.assign(kFapCount + 1, -1);
    for (std::size_t s = 0; s < model.faps.size(); ++s)
      fap_slot[static_cast<std::size_t>(model.faps[s])] = static_cast<int>(s);
    x.assign(6 + fap_count(), 0.0);
    previous.assign(fap_count(), 0.0);
    prior_gain.assign(fap_count(), 1.0);
    hold_gain.assign(fap_count(), 1.0);
    clamped.assign(fap_count(), false);
    for (int id : model.faps) {
      bounded.push_back(!fap_info(id).bidirectional && !o.signed_faps.count(id));
      const auto floor = o.lower_bounds.find(id);
      bound.push_back(floor == o.lower_bounds.end() ? 0.0 : std::min(0.0, floor->second));
    }
    for (const auto& rule : o.hold_while_hidden) {
      std::vector<std::size_t> on_point, held;
      for (std::size_t i = 0; i < model.markers.size(); ++i)
        if (model.markers[i].feature_point.str() == rule.feature_point) on_point.push_back(i);
      for (int id : rule.faps)
        if (is_fap_id(id) && fap_slot[static_cast<std::size_t>(id)] >= 0)
          held.push_back(static_cast<std::size_t>(fap_slot[static_cast<std::size_t>(id)]));
      if (!on_point.empty() && !held.empty()) holds.emplace_back(on_point, held);
    }

    set_neutral_pose();
    std::copy(neutral_pose, neutral_pose + 6, pose());
    set_shape_rates();

    if (options.loss == RobustLoss::Huber)
      loss = std::make_unique<ceres::HuberLoss>(options.loss_scale_px);
    if (options.loss == RobustLoss::Cauchy)
      loss = std::make_unique<ceres::CauchyLoss>(options.loss_scale_px);

    // Pixels per FAP unit at the neutral depth, for the prior's weight.
    const double depth = std::max(1.0, neutral_cv.translation[2]);
    px_per_unit.assign(fap_count(), 0.0);
    const int n = static_cast<int>(x.size());
    problem.AddParameterBlock(x.data(), n);
    for (std::size_t i = 0; i < model.markers.size(); ++i) {
      const ModelMarker& m = model.markers[i];
      for (const FapStep& s : m.faps) {
        const auto slot = static_cast<std::size_t>(fap_slot[static_cast<std::size_t>(s.fap)]);
        px_per_unit[slot] = std::max(px_per_unit[slot], s.step.norm() * cam.fx / depth);
      }
      costs.emplace_back(new MarkerResidual(&observations[i], m, fap_slot, &k, n));
      problem.AddResidualBlock(costs.back().get(), loss.get(), x.data());
    }
    measured_by.resize(fap_count());
    read_by.resize(fap_count());
    for (std::size_t i = 0; i < model.markers.size(); ++i)
      for (const FapStep& s : model.markers[i].faps) {
        const auto slot = static_cast<std::size_t>(fap_slot[static_cast<std::size_t>(s.fap)]);
        const double share = s.step.norm() * cam.fx / depth / px_per_unit[slot];
        if (share >= kMeasuringShare) measured_by[slot].push_back(i);
        if (share >= options.min_reading_share) read_by[slot].push_back(i);
      }
    if (options.pose_prior_weight > 0) {
      // Pixels per radian of rotation (the markers' RMS distance from their centroid as the
      // lever) and per millimetre of translation across / along the optical axis.
      Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
      for (const ModelMarker& m : model.markers) centroid += m.neutral;
      centroid /= static_cast<double>(std::max<std::size_t>(1, model.markers.size()));
      double spread = 0;
      for (const ModelMarker& m : model.markers) spread += (m.neutral - centroid).squaredNorm();
      const double lever =
          std::sqrt(spread / static_cast<double>(std::max<std::size_t>(1, model.markers.size())));
      const double w = options.pose_prior_weight, px_per_mm = cam.fx / depth;
      const std::vector<double> weights = {w * lever * px_per_mm, w * lever * px_per_mm,
                                           w * lever * px_per_mm, w * px_per_mm,
                                           w * px_per_mm,         w * lever * px_per_mm / depth};
      pose_target.assign(6, 0.0);
      pose_gain.assign(6, 0.0);
      costs.emplace_back(new PriorResiduals(&pose_target, &pose_gain, weights, n, 0));
      pose_loss = std::make_unique<ceres::HuberLoss>(w * options.pose_prior_scale_px);
      problem.AddResidualBlock(costs.back().get(), pose_loss.get(), x.data());
    }
    if (fap_count() > 0) {
      std::vector<double> weights;
      for (std::size_t s = 0; s < fap_count(); ++s) {
        const auto own = options.prior_weight_of.find(model.faps[s]);
        const double w = own == options.prior_weight_of.end() ? options.prior_weight : own->second;
        weights.push_back(w * px_per_unit[s]);
        hold_gain[s] = kHoldWeight / std::max(w, 1e-9);
      }
      costs.emplace_back(new PriorResiduals(&previous, &prior_gain, std::move(weights), n, 6));
      problem.AddResidualBlock(costs.back().get(), nullptr, x.data());
    }

    // A few dozen residuals over a few dozen parameters: dense normal equations are the
    // cheapest exact solve; one thread, no logging, no gradient checks.
    solver.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
    solver.max_num_iterations = options.max_iterations;
    solver.logging_type = ceres::SILENT;
    solver.minimizer_progress_to_stdout = false;
    solver.check_gradients = false;
    solver.num_threads = 1;
    solver.function_tolerance = options.function_tolerance;
    solver.parameter_tolerance = options.parameter_tolerance;
    solver.gradient_tolerance = 1e-10;
  }

  void set_neutral_pose() {
    if (profile.neutral_pose) {
      neutral_cv = *profile.neutral_pose;
    } else {
      // No recorded pose: PnP on the neutral shape and neutral image positions.
      std::vector<cv::Point3d> object;
      std::vector<cv::Point2d> image;
      for (const ModelMarker& m : model.markers) {
        object.emplace_back(m.neutral.x(), m.neutral.y(), m.neutral.z());
        image.push_back(profile.find_marker(m.marker)->image);
      }
      if (object.size() < 4)
        throw InputError("actor profile '" + profile.name +
                         "': fewer than 4 markers with 3D positions");
      cv::Vec3d r(M_PI, 0, 0), t(0, 0, 600);
      cv::solvePnP(object, image, cv::Mat(profile.camera.camera_matrix()), cv::Mat(), r, t, true);
      neutral_cv = {r, t};
    }
    cv::Matx33d r;
    cv::Rodrigues(neutral_cv.rotation, r);
    cv::Vec3d aa;
    cv::Rodrigues(r * flip(), aa);  // R_cv = R_fit F  =>  R_fit = R_cv F
    for (int i = 0; i < 3; ++i) {
      neutral_pose[i] = aa[i];
      neutral_pose[3 + i] = neutral_cv.translation[i];
    }
  }

  tracking::HeadPose current_pose() const {
    cv::Matx33d r;
    cv::Rodrigues(cv::Vec3d(x[0], x[1], x[2]), r);
    cv::Vec3d rv;
    cv::Rodrigues(r * flip(), rv);
    return {rv, {x[3], x[4], x[5]}};
  }

  // One recursive least-squares step on log f from this frame's fit: the gradient and the
  // information of the reprojection errors in log f, both marginalised over the frame's pose
  // and FAPs (Schur complement), so what the pose or the face could explain is not read as
  // a focal length. The residual Jacobian of fx X/Z + cx - u in log f is fx X/Z itself plus
  // the neutral shape's own move (set_shape_rates()): without that term the neutral frames,
  // which the calibration fitted at the old focal length, read as evidence for it.
  void refine_focal_length(const std::vector<std::size_t>& which) {
    const auto n = static_cast<Eigen::Index>(x.size());
    const auto markers = static_cast<Eigen::Index>(2 * which.size());
    const auto rows = markers + static_cast<Eigen::Index>(fap_count());
    Eigen::MatrixXd J(rows, n);
    Eigen::VectorXd r(rows), jf = Eigen::VectorXd::Zero(rows);
    const double* params[] = {x.data()};
    Eigen::Index row = 0;
    Eigen::Matrix<double, 2, Eigen::Dynamic, Eigen::RowMajor> jm(2, n);
    for (std::size_t i : which) {
      double* jac[] = {jm.data()};
      costs[i]->Evaluate(params, r.data() + row, jac);
      J.middleRows(row, 2) = jm;
      // The focal length itself, plus the neutral shape rebuilt at the new focal length.
      double shape[2];
      static_cast<const MarkerResidual*>(costs[i].get())->along(x.data(), shape_rate[i], shape);
      jf(row) = r(row) + observations[i].u - k.cx + shape[0];
      jf(row + 1) = r(row + 1) + observations[i].v - k.cy + shape[1];
      row += 2;
    }
    if (fap_count() > 0) {
      Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> jp(rows - markers, n);
      double* jac[] = {jp.data()};
      costs.back()->Evaluate(params, r.data() + row, jac);
      J.bottomRows(rows - markers) = jp;
    }
    const Eigen::MatrixXd H = J.transpose() * J;
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(H);
    const Eigen::VectorXd b = J.transpose() * jf;
    const Eigen::VectorXd h_b = ldlt.solve(b);
    const double information = jf.squaredNorm() - b.dot(h_b);
    const double gradient = jf.dot(r) - h_b.dot(J.transpose() * r);
    if (!std::isfinite(information) || !std::isfinite(gradient)) return;
    focal_information += std::max(0.0, information);
    const double next = std::clamp(log_focal - gradient / focal_information, -1.5, 1.5);
    set_log_focal(next);
  }

  // The neutral shape as the calibration would have built it at focal length f0 e^eps: the
  // neutral head moved away by e^eps (its image size kept) and each marker kept on its
  // neutral image ray q at its depth relative to the head: P(eps) = (q e^-eps d(eps), d(eps)),
  // d(eps) = d0 + (e^eps - 1) t0z, t0(eps) = (t0x, t0y, t0z e^eps), X = R0^T (P - t0).
  struct NeutralRay {
    Eigen::Vector2d q;  // normalised image position at f0 (z = 1)
    double depth = 0;   // camera depth at f0
  };
  std::vector<NeutralRay> rays;
  cv::Matx33d r0;
  Eigen::Vector3d t0;

  void set_shape_rates() {
    cv::Rodrigues(neutral_cv.rotation, r0);
    t0 = {neutral_cv.translation[0], neutral_cv.translation[1], neutral_cv.translation[2]};
    for (const ModelMarker& m : model.markers) {
      const cv::Vec3d pc = r0 * cv::Vec3d(m.neutral.x(), m.neutral.y(), m.neutral.z());
      const Eigen::Vector3d p = Eigen::Vector3d(pc[0], pc[1], pc[2]) + t0;
      rays.push_back({{p.x() / p.z(), p.y() / p.z()}, p.z()});
    }
    update_shape_rates();
  }

  Eigen::Vector3d to_head(const Eigen::Vector3d& in_camera) const {
    const cv::Vec3d h = r0.t() * cv::Vec3d(in_camera.x(), in_camera.y(), in_camera.z());
    return {h[0], h[1], h[2]};
  }

  // dX/d eps at the current eps, per marker.
  void update_shape_rates() {
    const double e = std::exp(log_focal);
    shape_rate.clear();
    for (const NeutralRay& ray : rays) {
      const double d = ray.depth + (e - 1) * t0.z();
      shape_rate.push_back(
          to_head({ray.q.x() * (t0.z() - d / e), ray.q.y() * (t0.z() - d / e), 0}));
    }
  }

  void set_log_focal(double next) {
    const double e0 = std::exp(log_focal), e = std::exp(next);
    log_focal = next;
    k.fx = base_fx * e;
    k.fy = base_fy * e;
    for (std::size_t i = 0; i < model.markers.size(); ++i) {
      const NeutralRay& ray = rays[i];
      auto neutral_at = [&](double s) {
        const double d = ray.depth + (s - 1) * t0.z();
        return to_head(Eigen::Vector3d(ray.q.x() / s * d, ray.q.y() / s * d, d) -
                       Eigen::Vector3d(t0.x(), t0.y(), t0.z() * s));
      };
      static_cast<MarkerResidual*>(costs[i].get())->move_neutral(neutral_at(e) - neutral_at(e0));
    }
    update_shape_rates();
    const double scale = e / e0;
    neutral_pose[5] *= scale;
    neutral_cv.translation[2] *= scale;
    x[5] *= scale;  // the next frame starts at the rescaled depth
    last_pose[5] *= scale;
    pose_velocity[5] *= scale;
  }

  void reset() {
    fitted_in_a_row = 0;
    std::fill(prior_gain.begin(), prior_gain.end(), 1.0);
    std::fill(clamped.begin(), clamped.end(), false);
    std::copy(neutral_pose, neutral_pose + 6, pose());
    std::fill(x.begin() + 6, x.end(), 0.0);
    std::fill(previous.begin(), previous.end(), 0.0);
  }

  // The starting pose: the previous frame's moved on by the last frame-to-frame motion
  // (constant velocity), which saves the turning head one or two iterations a frame. Not the
  // pose pull's smoothed target: started there, the fit took more iterations (4.49 against
  // 4.08 a frame on bench_mapping's take), as the smoothed velocity lags a turn.
  void predict_pose() {
    double now[6];
    std::copy(pose(), pose() + 6, now);
    if (fitted_in_a_row >= 2) {
      cv::Matx33d r_now, r_last;
      cv::Rodrigues(cv::Vec3d(now[0], now[1], now[2]), r_now);
      cv::Rodrigues(cv::Vec3d(last_pose[0], last_pose[1], last_pose[2]), r_last);
      cv::Vec3d aa;
      cv::Rodrigues(r_now * r_last.t() * r_now, aa);
      for (int i = 0; i < 3; ++i) {
        x[static_cast<std::size_t>(i)] = aa[i];
        x[static_cast<std::size_t>(3 + i)] = 2 * now[3 + i] - last_pose[3 + i];
      }
    }
    std::copy(now, now + 6, last_pose);
  }

  // Whether FAP slot s's left/right twin is measured this frame and fitted within
  // kTwinAgreementPx of it (see kMeasuringShare).
  bool near_measured_twin(std::size_t s, const std::vector<bool>& measured) const {
    const std::optional<int> twin = mirror_fap(model.faps[s]);
    if (!twin) return false;
    const int t = fap_slot[static_cast<std::size_t>(*twin)];
    if (t < 0 || !measured[static_cast<std::size_t>(t)]) return false;
    const double apart = std::abs(x[6 + s] - x[6 + static_cast<std::size_t>(t)]);
    return apart * px_per_unit[s] <= kTwinAgreementPx;
  }

  FitResult fit(const tracking::TrackedFrame& frame) {
    FitResult result;
    result.faps.index = frame.frame;
    result.faps.time_s = frame.time_s;

    for (auto& o : observations) o.active = false;
    std::vector<cv::Point2d> pixels;
    std::vector<std::size_t> which;
    for (const auto& m : frame.markers) {
      if (!m.valid || !std::isfinite(m.position.x) || !std::isfinite(m.position.y)) continue;
      auto it = marker_index.find(m.marker);
      if (it == marker_index.end()) continue;
      pixels.push_back(m.position);
      which.push_back(it->second);
    }
    if (static_cast<int>(which.size()) < options.min_markers) return result;
    if (profile.camera.has_distortion()) {
      const cv::Mat K(profile.camera.camera_matrix());
      cv::undistortPoints(pixels, pixels, K, cv::Mat(profile.camera.distortion), cv::noArray(), K);
    }
    for (std::size_t n = 0; n < which.size(); ++n) {
      observations[which[n]] = {pixels[n].x, pixels[n].y, true};
    }

    // A FAP no valid marker reads (SolverOptions::min_reading_share) is not reported: its
    // prior holds it near its previous value, which the fit still moves to explain a marker
    // it barely moves. One read but not measured is left to its twin when near it (see
    // kMeasuringShare).
    std::vector<bool> seen(fap_count(), false), measured(fap_count(), false);
    for (std::size_t s = 0; s < fap_count(); ++s) {
      for (std::size_t i : read_by[s]) seen[s] = seen[s] || observations[i].active;
      for (std::size_t i : measured_by[s]) measured[s] = measured[s] || observations[i].active;
    }
    // The pose prior's target: the previous pose moved on by the smoothed velocity.
    if (!pose_target.empty()) {
      for (std::size_t i = 0; i < 6; ++i) pose_target[i] = x[i] + pose_velocity[i];
      std::fill(pose_gain.begin(), pose_gain.end(), fitted_in_a_row >= 1 ? 1.0 : 0.0);
    }
    if (fitted_in_a_row == 0) {
      std::copy(neutral_pose, neutral_pose + 6, pose());
      std::fill(x.begin() + 6, x.end(), 0.0);
      std::fill(std::begin(pose_velocity), std::end(pose_velocity), 0.0);
    } else {
      predict_pose();
    }
    std::copy(x.begin() + 6, x.end(), previous.begin());

    // Unidirectional FAPs by an active set rather than Ceres' bounds. Ceres projects each step
    // onto the bounds after computing it without them, so a FAP resting on its bound (every
    // unidirectional FAP of a neutral face) cost 20-25 shrinking steps instead of 3. Here a
    // clamped FAP is pinned to its bound by its prior made kHoldWeight strong (a subset manifold
    // would hold it exactly but makes Ceres rebuild its evaluator: slower): start with the
    // previous frame's clamped set, pin those that end below their bound, release those the
    // markers pull above it, until the set holds.
    // Held FAPs keep the previous frame's value (their prior's target) with the hold's weight.
    std::vector<bool> held(fap_count(), false);
    for (const auto& [on_point, faps] : holds)
      if (std::none_of(on_point.begin(), on_point.end(),
                       [&](std::size_t i) { return observations[i].active; }))
        for (std::size_t s : faps) held[s] = true;
    for (std::size_t s = 0; s < fap_count(); ++s) {
      if (clamped[s]) previous[s] = bound[s];
      prior_gain[s] = clamped[s] || held[s] ? hold_gain[s] : 1.0;
    }
    ceres::Solver::Summary summary;
    for (int round = 0; round < 4; ++round) {
      ceres::Solve(solver, &problem, &summary);
      result.iterations += static_cast<int>(summary.iterations.size());
      if (!summary.IsSolutionUsable()) break;
      bool changed = false;
      for (std::size_t s = 0; s < fap_count(); ++s) {
        if (!bounded[s]) continue;
        if (!clamped[s] && x[6 + s] < bound[s]) {
          x[6 + s] = previous[s] = bound[s];
          clamped[s] = true;
          prior_gain[s] = hold_gain[s];
          changed = true;
        } else if (clamped[s] && x[6 + s] > bound[s] + 1e-9) {
          clamped[s] = false;  // the markers pull it off the bound
          prior_gain[s] = held[s] ? hold_gain[s] : 1.0;
          changed = true;
        }
      }
      if (!changed) break;
    }
    for (std::size_t s = 0; s < fap_count(); ++s)
      if (clamped[s]) x[6 + s] = bound[s];  // exactly on the bound
    result.markers_used = static_cast<int>(which.size());

    // RMS reprojection error without the robust loss, from the final state.
    double sq = 0;
    const double* params[] = {x.data()};
    for (std::size_t i : which) {
      double r[2];
      costs[i]->Evaluate(params, r, nullptr);
      sq += r[0] * r[0] + r[1] * r[1];
    }
    result.rms_px = std::sqrt(sq / static_cast<double>(which.size()));

    if (!summary.IsSolutionUsable() || !std::isfinite(summary.final_cost)) {
      reset();
      return result;
    }
    result.ok = true;
    result.focal_px = k.fx;
    if (refine_focal) refine_focal_length(which);
    if (fitted_in_a_row == 0) std::copy(pose(), pose() + 6, last_pose);
    if (fitted_in_a_row >= 1 && !pose_target.empty()) {
      // An alpha-beta filter's velocity step: the velocity learns a share of the prediction's
      // miss, so one noisy frame barely moves the next prediction.
      for (std::size_t i = 0; i < 6; ++i)
        pose_velocity[i] += options.pose_velocity_gain * (x[i] - pose_target[i]);
    }
    ++fitted_in_a_row;
    result.pose = current_pose();
    for (std::size_t s = 0; s < fap_count(); ++s)
      if (seen[s] && !measured[s] && near_measured_twin(s, measured)) seen[s] = false;
    for (std::size_t s = 0; s < fap_count(); ++s)
      if (seen[s]) {
        // A FAP fitted below 0 by SolverOptions::lower_bounds is reported on its bound.
        const double value = bounded[s] ? std::max(0.0, values()[s]) : values()[s];
        result.faps.set(model.faps[s], profile.apply_gain(model.faps[s], value));
      }
    if (options.head_faps) {
      const auto head = head_rotation_faps(neutral_cv, result.pose);
      for (int i = 0; i < 3; ++i)
        result.faps.set(48 + i, profile.apply_gain(48 + i, head[static_cast<std::size_t>(i)]));
    }
    return result;
  }
};

void SolverOptions::validate() const {
  const OptionCheck check("SolverOptions");
  check.positive("loss_scale_px", loss_scale_px).not_negative("prior_weight", prior_weight);
  for (const auto& [fap, weight] : prior_weight_of)
    check.not_negative(("prior_weight_of[" + std::to_string(fap) + "]").c_str(), weight);
  check.not_negative("pose_prior_weight", pose_prior_weight)
      .positive("pose_prior_scale_px", pose_prior_scale_px)
      .within("pose_velocity_gain", pose_velocity_gain, 0, 1)
      .within("min_reading_share", min_reading_share, 0, 1)
      .positive("max_iterations", max_iterations)
      .not_negative("function_tolerance", function_tolerance)
      .not_negative("parameter_tolerance", parameter_tolerance)
      .positive("min_markers", min_markers)
      .positive("focal_prior_sigma", focal_prior_sigma);
}

void set_solver_option(SolverOptions& options, const std::string& assignment) {
  using O = SolverOptions;
  static const std::vector<NamedOption<O>> table = {
      ROSTRO_NAMED_OPTION(O, model.fit_depth_faps), ROSTRO_NAMED_OPTION(O, loss_scale_px),
      ROSTRO_NAMED_OPTION(O, prior_weight),         ROSTRO_NAMED_OPTION(O, pose_prior_weight),
      ROSTRO_NAMED_OPTION(O, pose_prior_scale_px),  ROSTRO_NAMED_OPTION(O, pose_velocity_gain),
      ROSTRO_NAMED_OPTION(O, min_reading_share),    ROSTRO_NAMED_OPTION(O, max_iterations),
      ROSTRO_NAMED_OPTION(O, function_tolerance),   ROSTRO_NAMED_OPTION(O, parameter_tolerance),
      ROSTRO_NAMED_OPTION(O, min_markers),          ROSTRO_NAMED_OPTION(O, head_faps),
      ROSTRO_NAMED_OPTION(O, refine_default_focal), ROSTRO_NAMED_OPTION(O, focal_prior_sigma),
  };
  set_named_option(options, table, "SolverOptions", assignment);
}

FapSolver::FapSolver(const calib::ActorProfile& profile, const SolverOptions& options)
    : impl_(std::make_unique<Impl>(profile, validated(options))) {}
FapSolver::~FapSolver() = default;
FitResult FapSolver::fit(const tracking::TrackedFrame& frame) {
  return impl_->fit(frame);
}
void FapSolver::reset() {
  impl_->reset();
}
const MarkerModel& FapSolver::model() const {
  return impl_->model;
}
double FapSolver::focal_length() const {
  return impl_->k.fx;
}

}  // namespace rostro::mapping
