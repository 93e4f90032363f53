// MarkerResidual's hand-written Jacobian against Ceres' numeric derivatives
// (ceres::GradientChecker), at a turned head with the lower lip's FAPs set.
#include "mapping/marker_residual.hpp"

#include <ceres/gradient_checker.h>
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "tests/support/synthetic_face.hpp"

namespace rostro::mapping::internal {
namespace {

struct Scene {
  MarkerModel model;
  std::vector<int> fap_slot = std::vector<int>(69, -1);  // FAP id -> column - 6
  Intrinsics k{1000, 1000, 640, 360};
  std::vector<double> parameters;  // angle-axis, translation, every fitted FAP

  int size() const { return static_cast<int>(parameters.size()); }
};

// The synthetic actor's marker model; the head turned (about 26 degrees of yaw, 9 of pitch,
// 5 of roll) and 480 mm away; every FAP that moves a lower-lip marker (8.2, 8.7, 8.8) set
// to a few hundred units, alternately up and down.
Scene turned_head_lower_lip_set() {
  const auto actor = test::make_actor();
  Scene s;
  s.model = build_marker_model(test::exact_profile(actor, test::head_pose(0, 0, 0)));
  for (std::size_t j = 0; j < s.model.faps.size(); ++j)
    s.fap_slot[static_cast<std::size_t>(s.model.faps[j])] = static_cast<int>(j);
  s.parameters = {0.15, 0.45, 0.08, 12, -8, 480};
  s.parameters.resize(6 + s.model.faps.size(), 0.0);
  int sign = 1;
  for (const ModelMarker& m : s.model.markers) {
    if (m.feature_point.group != 8 ||
        (m.feature_point.index != 2 && m.feature_point.index != 7 && m.feature_point.index != 8))
      continue;
    for (const FapStep& f : m.faps) {
      double& value = s.parameters[6 + static_cast<std::size_t>(s.fap_slot[f.fap])];
      if (value == 0) value = sign * (150.0 + 10.0 * f.fap), sign = -sign;
    }
  }
  return s;
}

std::vector<const ModelMarker*> lower_lip(const Scene& s) {
  std::vector<const ModelMarker*> out;
  for (const ModelMarker& m : s.model.markers)
    if (m.feature_point.group == 8 &&
        (m.feature_point.index == 2 || m.feature_point.index == 7 || m.feature_point.index == 8))
      out.push_back(&m);
  return out;
}

ceres::GradientChecker::ProbeResults probe(const ceres::CostFunction& cost, const Scene& s,
                                           bool* passed) {
  const std::vector<const ceres::Manifold*>* euclidean = nullptr;
  ceres::GradientChecker checker(&cost, euclidean, ceres::NumericDiffOptions());
  const double* blocks[] = {s.parameters.data()};
  ceres::GradientChecker::ProbeResults results;
  *passed = checker.Probe(blocks, 1e-6, &results);
  return results;
}

TEST(MarkerResidual, JacobianMatchesNumericAtATurnedHeadWithTheLowerLipSet) {
  const Scene s = turned_head_lower_lip_set();
  const auto lip = lower_lip(s);
  ASSERT_EQ(lip.size(), 3u);
  for (const ModelMarker* m : lip) ASSERT_FALSE(m->faps.empty()) << m->marker;
  // Every marker of the model (the lower lip's, whose FAPs are set, and the rest, rigid or
  // at rest), observed off where the model projects it: a residual that is not zero.
  for (const ModelMarker& m : s.model.markers) {
    Observation seen{600, 420, true};
    const MarkerResidual cost(&seen, m, s.fap_slot, &s.k, s.size());
    bool passed = false;
    const auto results = probe(cost, s, &passed);
    EXPECT_TRUE(passed) << m.marker << ": " << results.error_log;
    EXPECT_LT(results.maximum_relative_error, 1e-6) << m.marker;
    EXPECT_GT(results.residuals.norm(), 1) << m.marker;
  }
}

// The twin: the checker does see a Jacobian off by 1 % in one FAP's column.
class SkewedResidual : public ceres::CostFunction {
 public:
  SkewedResidual(const MarkerResidual& inner, int column) : inner_(inner), column_(column) {
    set_num_residuals(2);
    mutable_parameter_block_sizes()->push_back(inner.parameter_block_sizes()[0]);
  }
  bool Evaluate(double const* const* values, double* r, double** jacobians) const override {
    if (!inner_.Evaluate(values, r, jacobians)) return false;
    if (jacobians && jacobians[0]) {
      const int n = parameter_block_sizes()[0];
      jacobians[0][column_] *= 1.01;
      jacobians[0][n + column_] *= 1.01;
    }
    return true;
  }

 private:
  const MarkerResidual& inner_;
  int column_;
};

TEST(MarkerResidual, CheckerSeesAJacobianOffByOnePercent) {
  const Scene s = turned_head_lower_lip_set();
  const ModelMarker& m = *lower_lip(s).front();
  Observation seen{600, 420, true};
  const MarkerResidual cost(&seen, m, s.fap_slot, &s.k, s.size());
  const SkewedResidual skewed(cost, 6 + s.fap_slot[static_cast<std::size_t>(m.faps.front().fap)]);
  bool passed = true;
  probe(skewed, s, &passed);
  EXPECT_FALSE(passed);
}

}  // namespace
}  // namespace rostro::mapping::internal
