#include "eval/plot.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "eval/eval_plots.hpp"

namespace rostro::eval {
namespace {

TEST(Plot, NiceTicksUseRoundSteps) {
  const auto t = nice_ticks(0, 0.1, 8);
  ASSERT_GE(t.size(), 5u);
  EXPECT_DOUBLE_EQ(t.front(), 0.0);
  EXPECT_NEAR(t.back(), 0.1, 1e-12);
  for (std::size_t i = 2; i < t.size(); ++i) EXPECT_NEAR(t[i] - t[i - 1], t[1] - t[0], 1e-12);
  const auto u = nice_ticks(-37, 212, 5);
  EXPECT_DOUBLE_EQ(u[1] - u[0], 50.0);
  EXPECT_DOUBLE_EQ(u.front(), 0.0);
  EXPECT_GE(u.front(), -37.0);
  EXPECT_LE(u.back(), 212.0);
}

TEST(Plot, CedChartIsWrittenAsAReadablePng) {
  CedRun run{"still head", {0.01, 0.02, 0.03, 0.05, std::numeric_limits<double>::infinity()}};
  const Chart c = ced_chart({run});
  ASSERT_EQ(c.series.size(), 1u);
  EXPECT_NE(c.series[0].label.find("AUC@0.08"), std::string::npos);
  const auto path = std::filesystem::path(ROSTRO_BINARY_DIR) / "test_eval_tmp" / "ced.png";
  std::filesystem::create_directories(path.parent_path());
  write_png(path, draw_chart(c, {900, 600}));
  const cv::Mat back = cv::imread(path.string());
  ASSERT_FALSE(back.empty());
  EXPECT_EQ(back.cols, 900);
  EXPECT_EQ(back.rows, 600);
  // Something besides the white background was drawn in the plot area's middle.
  cv::Mat gray;
  cv::cvtColor(back, gray, cv::COLOR_BGR2GRAY);
  EXPECT_LT(cv::mean(gray)[0], 250.0);
}

TEST(Plot, FapCurvesStackOnePanelPerFap) {
  FapStream truth, est;
  truth.header.fps = 25;
  for (int i = 0; i < 50; ++i) {
    FapFrame f;
    f.index = i;
    f.set(3, 100 * std::sin(i * 0.2));
    f.set(12, 20.0 * i);
    truth.frames.push_back(f);
    f.set(3, 90 * std::sin(i * 0.2));
    est.frames.push_back(f);
  }
  const auto charts = fap_curve_charts(truth, est, {3, 12});
  ASSERT_EQ(charts.size(), 2u);
  EXPECT_NE(charts[0].title.find("open_jaw"), std::string::npos);
  EXPECT_NEAR(charts[0].series[0].points[25].x, 1.0, 1e-12);
  const cv::Mat img = draw_charts(charts, {1000, 280});
  EXPECT_EQ(img.rows, 560);
  EXPECT_EQ(widest_range_faps(evaluate_faps(truth, est), 1), std::vector<int>{12});
}

}  // namespace
}  // namespace rostro::eval
