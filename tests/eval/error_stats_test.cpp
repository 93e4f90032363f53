#include "eval/error_stats.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace rostro::eval {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(ErrorStats, SummaryOfAKnownSample) {
  const std::vector<double> v{4, 1, 3, 2, 10};
  const ErrorStats s = summarize(v);
  EXPECT_EQ(s.count, 5u);
  EXPECT_DOUBLE_EQ(s.mean, 4.0);
  EXPECT_DOUBLE_EQ(s.median, 3.0);
  // Type 7: position 0.95 * 4 = 3.8 between 4 and 10.
  EXPECT_DOUBLE_EQ(s.p95, 4 + 0.8 * 6);
  EXPECT_DOUBLE_EQ(s.max, 10.0);
}

TEST(ErrorStats, SummaryIgnoresInfinityAndEmptyIsZero) {
  const std::vector<double> v{1, kInf, 3};
  const ErrorStats s = summarize(v);
  EXPECT_EQ(s.count, 2u);
  EXPECT_DOUBLE_EQ(s.mean, 2.0);
  EXPECT_EQ(summarize(std::vector<double>{}).count, 0u);
}

TEST(ErrorStats, AucAndFailureOfAHandMadeList) {
  // Contributions to AUC@0.08: 1, 0.75, 0.5, 0 (0.1 is beyond the threshold) -> 2.25 / 4.
  const std::vector<double> e{0.0, 0.02, 0.04, 0.1};
  EXPECT_DOUBLE_EQ(auc_at(e, 0.08), 0.5625);
  EXPECT_DOUBLE_EQ(failure_rate(e, 0.08), 0.25);
  EXPECT_DOUBLE_EQ(ced_at(e, 0.04), 0.75);
  EXPECT_DOUBLE_EQ(ced_at(e, 0.039), 0.5);
}

TEST(ErrorStats, UnscorableFramesFailAndLeaveTheCed) {
  const std::vector<double> e{0.04, kInf};
  EXPECT_DOUBLE_EQ(auc_at(e, 0.08), 0.25);
  EXPECT_DOUBLE_EQ(failure_rate(e, 0.08), 0.5);
  EXPECT_DOUBLE_EQ(ced_at(e, 1e9), 0.5);
}

TEST(ErrorStats, AnErrorExactlyAtTheThresholdIsNoFailure) {
  const std::vector<double> e{0.08};
  EXPECT_DOUBLE_EQ(failure_rate(e, 0.08), 0.0);
  EXPECT_DOUBLE_EQ(auc_at(e, 0.08), 0.0);
}

TEST(ErrorStats, ClosedFormAucMatchesNumericalIntegrationOfTheCed) {
  std::mt19937 rng(7);
  std::exponential_distribution<double> dist(30.0);
  std::vector<double> e(500);
  for (double& v : e) v = dist(rng);
  const int steps = 40000;
  double integral = 0;
  for (int i = 0; i < steps; ++i) integral += ced_at(e, (i + 0.5) * 0.08 / steps);
  integral /= steps;
  EXPECT_NEAR(auc_at(e, 0.08), integral, 1e-3);
}

TEST(ErrorStats, CedCurveIsAMonotoneStepFunctionEndingAtTheRange) {
  const std::vector<double> e{0.01, 0.03, 0.03, 0.2};
  const auto curve = ced_curve(e, 0.1);
  ASSERT_GE(curve.size(), 4u);
  EXPECT_DOUBLE_EQ(curve.front().x, 0.0);
  EXPECT_DOUBLE_EQ(curve.front().y, 0.0);
  EXPECT_DOUBLE_EQ(curve.back().x, 0.1);
  EXPECT_DOUBLE_EQ(curve.back().y, 0.75);
  for (std::size_t i = 1; i < curve.size(); ++i) {
    EXPECT_GE(curve[i].x, curve[i - 1].x);
    EXPECT_GE(curve[i].y, curve[i - 1].y);
  }
}

}  // namespace
}  // namespace rostro::eval
