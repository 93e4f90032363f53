#include "mapping/fap_solver.hpp"

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <cmath>
#include <opencv2/calib3d.hpp>
#include <unordered_map>
#include <vector>

#include "facecore/error.hpp"

namespace rostro::mapping {
namespace {

// The fit's rotation is taken relative to a camera-facing head: X_cam = R(aa) F X_head + t,
// F = diag(1, -1, -1) (head y up / z out -> image y down / toward the camera), so a frontal
// head is aa = 0, far from the angle-axis singularity at 180 degrees.
cv::Matx33d flip() {
  return {1, 0, 0, 0, -1, 0, 0, 0, -1};
}

struct Observation {
  double u = 0, v = 0;  // undistorted pixels
  bool active = false;
};

struct Intrinsics {
  double fx, fy, cx, cy;
};

// The reprojection error of a marker at `x` (face frame, y up, z out of the face) seen
// through the head pose (angle-axis, translation; camera frame, y down, z forward).
template <typename T>
void project(const T* pose, const T* x, const Intrinsics& k, const Observation& obs, T* r) {
  const T flipped[3] = {x[0], -x[1], -x[2]};
  T c[3];
  ceres::AngleAxisRotatePoint(pose, flipped, c);
  c[0] += pose[3];
  c[1] += pose[4];
  c[2] += pose[5];
  r[0] = k.fx * c[0] / c[2] + k.cx - obs.u;
  r[1] = k.fy * c[1] / c[2] + k.cy - obs.v;
}

// Reprojection residual of one marker moved by N FAPs.
template <int N>
struct MarkerResidual {
  const Observation* obs;
  Eigen::Vector3d neutral;
  std::array<Eigen::Vector3d, N> steps;
  Intrinsics k;

  template <typename T>
  bool residual(const T* pose, const T* const* faps, T* r) const {
    if (!obs->active) {
      r[0] = T(0);
      r[1] = T(0);
      return true;
    }
    T x[3] = {T(neutral.x()), T(neutral.y()), T(neutral.z())};
    for (int i = 0; i < N; ++i)
      for (int a = 0; a < 3; ++a) x[a] += faps[i][0] * steps[static_cast<std::size_t>(i)][a];
    project(pose, x, k, *obs, r);
    return true;
  }
};

struct Residual0 : MarkerResidual<0> {
  template <typename T>
  bool operator()(const T* pose, T* r) const {
    return residual<T>(pose, nullptr, r);
  }
};
struct Residual1 : MarkerResidual<1> {
  template <typename T>
  bool operator()(const T* pose, const T* f0, T* r) const {
    const T* f[] = {f0};
    return residual<T>(pose, f, r);
  }
};
struct Residual2 : MarkerResidual<2> {
  template <typename T>
  bool operator()(const T* pose, const T* f0, const T* f1, T* r) const {
    const T* f[] = {f0, f1};
    return residual<T>(pose, f, r);
  }
};
struct Residual3 : MarkerResidual<3> {
  template <typename T>
  bool operator()(const T* pose, const T* f0, const T* f1, const T* f2, T* r) const {
    const T* f[] = {f0, f1, f2};
    return residual<T>(pose, f, r);
  }
};

// A marker moved by more FAPs (the head's deformation can couple many FAPs to one point, e.g.
// the jaw and every lower-lip FAP to a lower-lip marker): parameter blocks pose, then one per FAP.
struct ResidualMany {
  const Observation* obs;
  Eigen::Vector3d neutral;
  std::vector<Eigen::Vector3d> steps;
  Intrinsics k;

  template <typename T>
  bool operator()(T const* const* blocks, T* r) const {
    if (!obs->active) {
      r[0] = T(0);
      r[1] = T(0);
      return true;
    }
    const T* pose = blocks[0];
    T x[3] = {T(neutral.x()), T(neutral.y()), T(neutral.z())};
    for (std::size_t i = 0; i < steps.size(); ++i)
      for (int a = 0; a < 3; ++a) x[a] += blocks[i + 1][0] * steps[i][a];
    project(pose, x, k, *obs, r);
    return true;
  }
};

ceres::CostFunction* make_cost_many(const Observation* obs, const ModelMarker& m,
                                    const Intrinsics& k) {
  auto* f = new ResidualMany{obs, m.neutral, {}, k};
  for (const FapStep& s : m.faps) f->steps.push_back(s.step);
  auto* cost = new ceres::DynamicAutoDiffCostFunction<ResidualMany, 8>(f);
  cost->AddParameterBlock(6);
  for (std::size_t i = 0; i < m.faps.size(); ++i) cost->AddParameterBlock(1);
  cost->SetNumResiduals(2);
  return cost;
}

// weight_i * (value_i - target_i) for every fitted FAP: the weak pull toward the previous
// frame, one residual block (each FAP its own size-1 parameter block) with an analytic
// Jacobian, since a block per FAP costs the solver's bookkeeping more than the arithmetic.
class PriorResiduals : public ceres::CostFunction {
 public:
  PriorResiduals(const std::vector<double>* targets, std::vector<double> weights)
      : targets_(targets), weights_(std::move(weights)) {
    set_num_residuals(static_cast<int>(weights_.size()));
    for (std::size_t i = 0; i < weights_.size(); ++i) mutable_parameter_block_sizes()->push_back(1);
  }
  bool Evaluate(double const* const* values, double* residuals, double** jacobians) const override {
    const std::size_t n = weights_.size();
    for (std::size_t i = 0; i < n; ++i)
      residuals[i] = weights_[i] * (values[i][0] - (*targets_)[i]);
    if (jacobians)
      for (std::size_t i = 0; i < n; ++i)
        if (jacobians[i])
          for (std::size_t r = 0; r < n; ++r) jacobians[i][r] = r == i ? weights_[i] : 0.0;
    return true;
  }

 private:
  const std::vector<double>* targets_;
  std::vector<double> weights_;
};

template <int N, typename Functor>
ceres::CostFunction* make_cost(const Observation* obs, const ModelMarker& m, const Intrinsics& k) {
  auto* f = new Functor;
  f->obs = obs;
  f->neutral = m.neutral;
  for (int i = 0; i < N; ++i)
    f->steps[static_cast<std::size_t>(i)] = m.faps[static_cast<std::size_t>(i)].step;
  f->k = k;
  if constexpr (N == 0) return new ceres::AutoDiffCostFunction<Functor, 2, 6>(f);
  if constexpr (N == 1) return new ceres::AutoDiffCostFunction<Functor, 2, 6, 1>(f);
  if constexpr (N == 2) return new ceres::AutoDiffCostFunction<Functor, 2, 6, 1, 1>(f);
  if constexpr (N == 3) return new ceres::AutoDiffCostFunction<Functor, 2, 6, 1, 1, 1>(f);
}

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
  std::vector<int> fap_slot;             // FAP id -> index in values, -1 when not fitted
  std::vector<double> values, previous;  // per fitted FAP
  std::vector<std::vector<std::size_t>> markers_of_fap;  // fitted FAP -> markers moving it
  double pose[6] = {0, 0, 0, 0, 0, 0};
  double neutral_pose[6] = {0, 0, 0, 0, 0, 0};
  tracking::HeadPose neutral_cv;
  std::unique_ptr<ceres::LossFunction> loss;
  std::vector<std::unique_ptr<ceres::CostFunction>> costs;
  ceres::Problem problem;
  ceres::Solver::Options solver;
  bool have_previous = false;

  static ceres::Problem::Options problem_options() {
    ceres::Problem::Options o;
    o.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    o.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    return o;
  }

  Impl(const calib::ActorProfile& p, const SolverOptions& o)
      : profile(p), options(o), model(build_marker_model(p, o.model)), problem(problem_options()) {
    const auto& cam = p.camera;
    k = {cam.fx, cam.fy, cam.cx, cam.cy};
    observations.resize(model.markers.size());
    for (std::size_t i = 0; i < model.markers.size(); ++i)
      marker_index[model.markers[i].marker] = i;
    fap_slot.assign(kFapCount + 1, -1);
    for (std::size_t s = 0; s < model.faps.size(); ++s)
      fap_slot[static_cast<std::size_t>(model.faps[s])] = static_cast<int>(s);
    values.assign(model.faps.size(), 0.0);
    previous.assign(model.faps.size(), 0.0);
    markers_of_fap.resize(model.faps.size());

    set_neutral_pose();
    std::copy(neutral_pose, neutral_pose + 6, pose);

    if (options.loss == RobustLoss::Huber)
      loss = std::make_unique<ceres::HuberLoss>(options.loss_scale_px);
    if (options.loss == RobustLoss::Cauchy)
      loss = std::make_unique<ceres::CauchyLoss>(options.loss_scale_px);

    // Pixels per FAP unit at the neutral depth, for the prior's weight.
    const double depth = std::max(1.0, neutral_cv.translation[2]);
    std::vector<double> px_per_unit(model.faps.size(), 0.0);
    problem.AddParameterBlock(pose, 6);
    for (double& v : values) problem.AddParameterBlock(&v, 1);
    for (std::size_t i = 0; i < model.markers.size(); ++i) {
      const ModelMarker& m = model.markers[i];
      std::vector<double*> blocks{pose};
      for (const FapStep& s : m.faps) {
        const auto slot = static_cast<std::size_t>(fap_slot[static_cast<std::size_t>(s.fap)]);
        blocks.push_back(&values[slot]);
        markers_of_fap[slot].push_back(i);
        px_per_unit[slot] = std::max(px_per_unit[slot], s.step.norm() * cam.fx / depth);
      }
      ceres::CostFunction* cost = nullptr;
      switch (m.faps.size()) {
        case 0:
          cost = make_cost<0, Residual0>(&observations[i], m, k);
          break;
        case 1:
          cost = make_cost<1, Residual1>(&observations[i], m, k);
          break;
        case 2:
          cost = make_cost<2, Residual2>(&observations[i], m, k);
          break;
        case 3:
          cost = make_cost<3, Residual3>(&observations[i], m, k);
          break;
        default:
          cost = make_cost_many(&observations[i], m, k);
      }
      costs.emplace_back(cost);
      problem.AddResidualBlock(cost, loss.get(), blocks);
    }
    if (!values.empty()) {
      std::vector<double> weights;
      std::vector<double*> blocks;
      for (std::size_t s = 0; s < values.size(); ++s) {
        weights.push_back(options.prior_weight * px_per_unit[s]);
        blocks.push_back(&values[s]);
      }
      auto* prior = new PriorResiduals(&previous, std::move(weights));
      costs.emplace_back(prior);
      problem.AddResidualBlock(prior, nullptr, blocks);
    }
    for (std::size_t s = 0; s < model.faps.size(); ++s)
      if (!fap_info(model.faps[s]).bidirectional)
        problem.SetParameterLowerBound(&values[s], 0, 0.0);

    solver.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
    solver.max_num_iterations = options.max_iterations;
    solver.logging_type = ceres::SILENT;
    solver.minimizer_progress_to_stdout = false;
    solver.num_threads = 1;
    solver.function_tolerance = 1e-6;
    solver.parameter_tolerance = 1e-6;
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
    cv::Rodrigues(cv::Vec3d(pose[0], pose[1], pose[2]), r);
    cv::Vec3d rv;
    cv::Rodrigues(r * flip(), rv);
    return {rv, {pose[3], pose[4], pose[5]}};
  }

  void reset() {
    have_previous = false;
    std::copy(neutral_pose, neutral_pose + 6, pose);
    std::fill(values.begin(), values.end(), 0.0);
    std::fill(previous.begin(), previous.end(), 0.0);
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

    // A FAP no valid marker sees is held at its previous value and not reported.
    std::vector<bool> seen(values.size(), false);
    for (std::size_t s = 0; s < values.size(); ++s) {
      for (std::size_t i : markers_of_fap[s]) seen[s] = seen[s] || observations[i].active;
      if (seen[s])
        problem.SetParameterBlockVariable(&values[s]);
      else
        problem.SetParameterBlockConstant(&values[s]);
    }
    if (!have_previous) {
      std::copy(neutral_pose, neutral_pose + 6, pose);
      std::fill(values.begin(), values.end(), 0.0);
    }
    previous = values;

    ceres::Solver::Summary summary;
    ceres::Solve(solver, &problem, &summary);
    result.iterations = static_cast<int>(summary.iterations.size());
    result.markers_used = static_cast<int>(which.size());

    // RMS reprojection error without the robust loss, from the final state.
    double sq = 0;
    for (std::size_t i : which) {
      double r[2];
      const ModelMarker& m = model.markers[i];
      std::vector<const double*> params{pose};
      for (const FapStep& f : m.faps)
        params.push_back(
            &values[static_cast<std::size_t>(fap_slot[static_cast<std::size_t>(f.fap)])]);
      costs[i]->Evaluate(params.data(), r, nullptr);
      sq += r[0] * r[0] + r[1] * r[1];
    }
    result.rms_px = std::sqrt(sq / static_cast<double>(which.size()));

    if (!summary.IsSolutionUsable() || !std::isfinite(summary.final_cost)) {
      reset();
      return result;
    }
    result.ok = true;
    have_previous = true;
    result.pose = current_pose();
    for (std::size_t s = 0; s < values.size(); ++s)
      if (seen[s]) result.faps.set(model.faps[s], profile.apply_gain(model.faps[s], values[s]));
    if (options.head_faps) {
      const auto head = head_rotation_faps(neutral_cv, result.pose);
      for (int i = 0; i < 3; ++i)
        result.faps.set(48 + i, profile.apply_gain(48 + i, head[static_cast<std::size_t>(i)]));
    }
    return result;
  }
};

FapSolver::FapSolver(const calib::ActorProfile& profile, const SolverOptions& options)
    : impl_(std::make_unique<Impl>(profile, options)) {}
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

}  // namespace rostro::mapping
