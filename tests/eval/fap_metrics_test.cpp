#include "eval/fap_metrics.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "facecore/error.hpp"

namespace rostro::eval {
namespace {

FapStream stream(const std::vector<std::vector<std::pair<int, double>>>& frames, long first = 0) {
  FapStream s;
  s.header.fps = 25;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    FapFrame f;
    f.index = first + static_cast<long>(i);
    f.time_s = static_cast<double>(f.index) / 25.0;
    for (const auto& [id, v] : frames[i]) f.set(id, v);
    s.frames.push_back(f);
  }
  return s;
}

const FapError* find(const FapEvalResult& r, int id) {
  for (const FapError& f : r.faps)
    if (f.fap == id) return &f;
  return nullptr;
}

TEST(FapMetrics, RmsShareOfRangeAndCorrelation) {
  // FAP 3: estimate 10 above the truth everywhere -> RMS 10, range 300, correlation 1.
  // FAP 5: estimate mirrors the truth -> correlation -1, RMS = sqrt(mean((2v)^2)).
  const auto truth = stream({{{3, 0}, {5, 10}, {19, 7}},
                             {{3, 100}, {5, -10}},
                             {{3, 200}, {5, 10}},
                             {{3, 300}, {5, -10}}});
  const auto est = stream({{{3, 10}, {5, -10}},
                           {{3, 110}, {5, 10}},
                           {{3, 210}, {5, -10}},
                           {{3, 310}, {5, 10}, {19, 1}}});
  const FapEvalResult r = evaluate_faps(truth, est);
  EXPECT_EQ(r.matched_frames, 4);
  ASSERT_EQ(r.faps.size(), 2u);  // FAP 19 is never set in both in the same frame
  const FapError* f3 = find(r, 3);
  ASSERT_NE(f3, nullptr);
  EXPECT_EQ(f3->frames, 4);
  EXPECT_NEAR(f3->rms, 10.0, 1e-12);
  EXPECT_NEAR(f3->mean_error, 10.0, 1e-12);
  ASSERT_TRUE(f3->rms_share_of_range.has_value());
  EXPECT_NEAR(*f3->rms_share_of_range, 10.0 / 300.0, 1e-12);
  ASSERT_TRUE(f3->correlation.has_value());
  EXPECT_NEAR(*f3->correlation, 1.0, 1e-12);
  const FapError* f5 = find(r, 5);
  ASSERT_NE(f5, nullptr);
  EXPECT_NEAR(f5->rms, 20.0, 1e-12);
  EXPECT_NEAR(*f5->rms_share_of_range, 1.0, 1e-12);
  EXPECT_NEAR(*f5->correlation, -1.0, 1e-12);
  EXPECT_NEAR(r.mean_rms, 15.0, 1e-12);
}

TEST(FapMetrics, FramesMatchByNumberAndConstantTruthHasNoShare) {
  const auto truth = stream({{{4, 50}}, {{4, 50}}, {{4, 50}}}, 10);
  const auto est = stream({{{4, 40}}, {{4, 60}}}, 11);  // frames 11 and 12
  const FapEvalResult r = evaluate_faps(truth, est);
  EXPECT_EQ(r.matched_frames, 2);
  ASSERT_EQ(r.faps.size(), 1u);
  EXPECT_NEAR(r.faps[0].rms, 10.0, 1e-12);
  EXPECT_FALSE(r.faps[0].rms_share_of_range.has_value());
  EXPECT_FALSE(r.faps[0].correlation.has_value());
  EXPECT_FALSE(r.mean_share_of_range.has_value());
}

TEST(FapMetrics, NoCommonFrameOrARepeatedFrameIsAnInputError) {
  EXPECT_THROW(evaluate_faps(stream({{{3, 1}}}, 0), stream({{{3, 1}}}, 5)), InputError);
  auto repeated = stream({{{3, 1}}, {{3, 2}}});
  repeated.frames[1].index = 0;
  EXPECT_THROW(evaluate_faps(repeated, repeated), InputError);
}

TEST(FapMetrics, PearsonOfKnownSeries) {
  EXPECT_NEAR(*pearson({1, 2, 3, 4}, {2, 4, 6, 8}), 1.0, 1e-12);
  EXPECT_NEAR(*pearson({1, 2, 3}, {1, 3, 2}), 0.5, 1e-12);
  EXPECT_FALSE(pearson({1, 1, 1}, {1, 2, 3}).has_value());
  EXPECT_FALSE(pearson({1}, {1}).has_value());
}

}  // namespace
}  // namespace rostro::eval
