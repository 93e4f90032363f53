#pragma once
// One marker's reprojection error in the per-frame fit (fap_solver.hpp), with its hand-written
// Jacobian; internal to the mapping library (FapSolver builds one per model marker; the test
// checks the Jacobian against numeric derivatives: tests/mapping/marker_residual_test.cpp).

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <Eigen/Core>
#include <algorithm>
#include <cstddef>
#include <vector>

#include "mapping/marker_model.hpp"

namespace rostro::mapping::internal {

struct Observation {
  double u = 0, v = 0;  // undistorted pixels
  bool active = false;
};

struct Intrinsics {
  double fx, fy, cx, cy;
};

// The reprojection error of one marker, with an analytic Jacobian over the one parameter
// block the fit has: [angle-axis (3), translation (3), every fitted FAP]. The marker sits at
// x = neutral + sum_k value_k step_k (face frame, y up, z out of the face) and is seen through
// X_cam = R(aa) F x + t (camera frame, y down, z forward). One block and hand-written
// derivatives: automatic differentiation over a block per FAP cost more than the arithmetic
// (the lower lip moves with up to a dozen FAPs), and Ceres' bookkeeping grows with the blocks.
class MarkerResidual : public ceres::CostFunction {
 public:
  MarkerResidual(const Observation* obs, const ModelMarker& m, const std::vector<int>& fap_slot,
                 const Intrinsics* k, int parameters)
      : obs_(obs), neutral_(m.neutral), k_(k) {
    for (const FapStep& s : m.faps)
      steps_.push_back({6 + fap_slot[static_cast<std::size_t>(s.fap)], s.step});
    set_num_residuals(2);
    mutable_parameter_block_sizes()->push_back(parameters);
  }

  bool Evaluate(double const* const* values, double* r, double** jacobians) const override {
    const double* p = values[0];
    double* J = jacobians ? jacobians[0] : nullptr;
    const int n = parameter_block_sizes()[0];
    if (J) std::fill(J, J + 2 * n, 0.0);
    if (!obs_->active) {
      r[0] = r[1] = 0.0;
      return true;
    }
    Eigen::Vector3d x = neutral_;
    for (const Step& s : steps_) x += p[s.column] * s.step;
    const Eigen::Vector3d y(x.x(), -x.y(), -x.z());  // F x
    // R(aa) y and its derivative in aa, from dual numbers over the three rotation parameters.
    using Jet = ceres::Jet<double, 3>;
    const Jet aa[3] = {Jet(p[0], 0), Jet(p[1], 1), Jet(p[2], 2)};
    const Jet yj[3] = {Jet(y.x()), Jet(y.y()), Jet(y.z())};
    Jet rotated[3];
    ceres::AngleAxisRotatePoint(aa, yj, rotated);
    const Eigen::Vector3d c(rotated[0].a + p[3], rotated[1].a + p[4], rotated[2].a + p[5]);
    const double iz = 1.0 / c.z();
    const Intrinsics& k = *k_;
    r[0] = k.fx * c.x() * iz + k.cx - obs_->u;
    r[1] = k.fy * c.y() * iz + k.cy - obs_->v;
    if (!J) return true;
    // d r / d c (2 x 3).
    const double a0 = k.fx * iz, a2 = -k.fx * c.x() * iz * iz;
    const double b1 = k.fy * iz, b2 = -k.fy * c.y() * iz * iz;
    double* J0 = J;      // row 0
    double* J1 = J + n;  // row 1
    for (int i = 0; i < 3; ++i) {
      J0[i] = a0 * rotated[0].v[i] + a2 * rotated[2].v[i];
      J1[i] = b1 * rotated[1].v[i] + b2 * rotated[2].v[i];
    }
    J0[3] = a0;
    J0[5] = a2;
    J1[4] = b1;
    J1[5] = b2;
    if (steps_.empty()) return true;
    // d c / d x = R F: rotate each step (F applied) with the rotation's value part.
    double R[9];
    ceres::AngleAxisToRotationMatrix(p, ceres::RowMajorAdapter3x3(R));
    for (const Step& s : steps_) {
      const Eigen::Vector3d d(s.step.x(), -s.step.y(), -s.step.z());
      const double d0 = R[0] * d.x() + R[1] * d.y() + R[2] * d.z();
      const double d1 = R[3] * d.x() + R[4] * d.y() + R[5] * d.z();
      const double d2 = R[6] * d.x() + R[7] * d.y() + R[8] * d.z();
      J0[s.column] += a0 * d0 + a2 * d2;
      J1[s.column] += b1 * d1 + b2 * d2;
    }
    return true;
  }

  // The change of the residual (2) per unit move of the marker's neutral position along v
  // (head frame): d r / d c  R(aa) F v.
  void along(const double* p, const Eigen::Vector3d& v, double* out) const {
    double R[9];
    ceres::AngleAxisToRotationMatrix(p, ceres::RowMajorAdapter3x3(R));
    Eigen::Vector3d x = neutral_;
    for (const Step& s : steps_) x += p[s.column] * s.step;
    const Eigen::Vector3d y(x.x(), -x.y(), -x.z()), d(v.x(), -v.y(), -v.z());
    Eigen::Vector3d c, dc;
    for (int i = 0; i < 3; ++i) {
      c[i] = R[3 * i] * y.x() + R[3 * i + 1] * y.y() + R[3 * i + 2] * y.z() + p[3 + i];
      dc[i] = R[3 * i] * d.x() + R[3 * i + 1] * d.y() + R[3 * i + 2] * d.z();
    }
    const double iz = 1.0 / c.z();
    out[0] = k_->fx * iz * (dc.x() - c.x() * iz * dc.z());
    out[1] = k_->fy * iz * (dc.y() - c.y() * iz * dc.z());
  }
  void move_neutral(const Eigen::Vector3d& by) { neutral_ += by; }

 private:
  struct Step {
    int column;  // in the parameter block
    Eigen::Vector3d step;
  };
  const Observation* obs_;
  Eigen::Vector3d neutral_;
  std::vector<Step> steps_;
  const Intrinsics* k_;  // the solver's: the focal length may be refined as frames come
};

}  // namespace rostro::mapping::internal
