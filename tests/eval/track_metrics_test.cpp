#include "eval/track_metrics.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "facecore/error.hpp"

namespace rostro::eval {
namespace {

using tracking::MarkerObservation;
using tracking::TrackedFrame;

MarkerObservation obs(const std::string& fp, double x, double y, bool valid = true) {
  MarkerObservation m;
  m.marker = "m" + fp;
  m.feature_point = *parse_feature_point(fp);
  m.position = {x, y};
  m.valid = valid;
  m.quality = 1;
  return m;
}

// Eye corners 100 px apart (3.12 at x=100, 3.7 at x=200) and two mouth corners 60 px apart.
TrackedFrame truth_frame(long frame) {
  TrackedFrame f;
  f.frame = frame;
  f.time_s = static_cast<double>(frame) / 30.0;
  f.markers = {obs("3.12", 100, 100), obs("3.7", 200, 100), obs("8.4", 120, 200),
               obs("8.3", 180, 200)};
  return f;
}

TrackedFrame shifted(const TrackedFrame& t, double dx, double dy) {
  TrackedFrame e = t;
  for (auto& m : e.markers) m.position += cv::Point2d(dx, dy);
  return e;
}

std::vector<TrackedFrame> truth_sequence(int n) {
  std::vector<TrackedFrame> frames;
  for (int i = 0; i < n; ++i) frames.push_back(truth_frame(i));
  return frames;
}

TEST(TrackMetrics, AConstantOffsetGivesAKnownNme) {
  const auto truth = truth_sequence(10);
  std::vector<TrackedFrame> est;
  for (const auto& t : truth) est.push_back(shifted(t, 3, 4));  // 5 px off, d = 100 px
  const TrackEvalResult r = evaluate_tracks(truth, est);
  EXPECT_EQ(r.scored_frames, 10);
  EXPECT_DOUBLE_EQ(r.norm_distance_median, 100.0);
  EXPECT_NEAR(r.nme.mean, 0.05, 1e-12);
  EXPECT_NEAR(r.nme.max, 0.05, 1e-12);
  EXPECT_NEAR(r.error_px.mean, 5.0, 1e-12);
  EXPECT_NEAR(r.auc, 1.0 - 0.05 / 0.08, 1e-12);
  EXPECT_DOUBLE_EQ(r.failure_rate, 0.0);
  EXPECT_EQ(r.lost_observations, 0);
  EXPECT_EQ(r.swap_observations, 0);
  EXPECT_EQ(r.astray_observations, 0);  // 5 px is not beyond 0.05 * 100 px
  ASSERT_EQ(r.markers.size(), 4u);
  EXPECT_EQ(r.markers[0].marker, "m3.12");  // truth order
  EXPECT_EQ(r.markers[2].scored, 10);
  EXPECT_NEAR(r.markers[2].error_px.p95, 5.0, 1e-12);
}

TEST(TrackMetrics, AnotherNormalisingPairChangesTheScale) {
  const auto truth = truth_sequence(3);
  std::vector<TrackedFrame> est;
  for (const auto& t : truth) est.push_back(shifted(t, 6, 0));
  TrackEvalOptions o;
  o.norm_a = "8.3";
  o.norm_b = "m8.4";  // a marker id works too
  const TrackEvalResult r = evaluate_tracks(truth, est, o);
  EXPECT_DOUBLE_EQ(r.norm_distance_median, 60.0);
  EXPECT_NEAR(r.nme.mean, 0.1, 1e-12);
  EXPECT_DOUBLE_EQ(r.failure_rate, 1.0);
  EXPECT_DOUBLE_EQ(r.auc, 0.0);
}

TEST(TrackMetrics, ASwapIsCounted) {
  const auto truth = truth_sequence(6);
  std::vector<TrackedFrame> est = truth;
  // Frames 2..4: the two mouth corners trade places; frame 5 they are right again.
  for (int i = 2; i <= 4; ++i) std::swap(est[i].markers[2].position, est[i].markers[3].position);
  const TrackEvalResult r = evaluate_tracks(truth, est);
  EXPECT_EQ(r.swap_observations, 6);  // two markers x three frames
  EXPECT_EQ(r.swap_events, 2);        // one run per marker
  EXPECT_EQ(r.markers[2].swap_events, 1);
  EXPECT_EQ(r.markers[3].swap_frames, 3);
  EXPECT_EQ(r.frames[3].swaps, 2);
  EXPECT_EQ(r.frames[5].swaps, 0);
  // Each swapped frame: two markers 60 px off out of four -> NME (0+0+60+60)/4/100 = 0.3.
  EXPECT_NEAR(r.frames[2].nme, 0.3, 1e-12);
}

TEST(TrackMetrics, AMarkerFarFromItsDotButNearNoOtherIsAstray) {
  const auto truth = truth_sequence(4);
  std::vector<TrackedFrame> est = truth;
  // Frames 1..3: the left mouth corner 20 px below its dot (on the lip, say), nearer its own
  // truth than any other marker's.
  for (int i = 1; i <= 3; ++i) est[i].markers[3].position += cv::Point2d(0, 20);
  const TrackEvalResult r = evaluate_tracks(truth, est);
  EXPECT_EQ(r.astray_observations, 3);
  EXPECT_EQ(r.swap_observations, 0);
  EXPECT_EQ(r.markers[3].astray_frames, 3);
  EXPECT_EQ(r.frames[0].astray, 0);
  EXPECT_EQ(r.frames[2].astray, 1);
  // The same 20 px toward the other mouth corner is a swap, not astray.
  for (int i = 1; i <= 3; ++i) est[i].markers[3].position = truth[i].markers[3].position;
  est[2].markers[3].position += cv::Point2d(-40, 0);
  const TrackEvalResult s = evaluate_tracks(truth, est);
  EXPECT_EQ(s.astray_observations, 0);
  EXPECT_EQ(s.swap_observations, 1);
}

TEST(TrackMetrics, ASmallErrorNearAnotherMarkerIsNoSwap) {
  auto truth = truth_sequence(1);
  // Two markers only 4 px apart; the estimate of one lands 3 px off, nearer the other.
  truth[0].markers[3].position = truth[0].markers[2].position + cv::Point2d(4, 0);
  auto est = truth;
  est[0].markers[2].position += cv::Point2d(3, 0);
  const TrackEvalResult r = evaluate_tracks(truth, est);
  EXPECT_EQ(r.swap_observations, 0);  // 3 px < 0.05 * 100 px
  TrackEvalOptions strict;
  strict.swap_threshold = 0.01;
  EXPECT_EQ(evaluate_tracks(truth, est, strict).swap_observations, 1);
}

TEST(TrackMetrics, LostFramesAreCounted) {
  const auto truth = truth_sequence(5);
  std::vector<TrackedFrame> est = truth;
  est[1].markers[2].valid = false;                   // invalid
  est[2].markers.erase(est[2].markers.begin() + 3);  // missing from the estimate
  est.erase(est.begin() + 3);                        // frame 3 missing entirely
  const TrackEvalResult r = evaluate_tracks(truth, est);
  EXPECT_EQ(r.lost_observations, 1 + 1 + 4);
  EXPECT_EQ(r.lost_frames, 3);
  EXPECT_EQ(r.missing_frames, 1);
  EXPECT_EQ(r.markers[2].lost, 2);
  EXPECT_EQ(r.markers[3].lost, 2);
  EXPECT_TRUE(std::isinf(r.frames[3].nme));
  EXPECT_DOUBLE_EQ(r.frames[1].nme, 0.0);  // the lost marker does not enter its NME
  EXPECT_DOUBLE_EQ(r.failure_rate, 0.2);
  EXPECT_DOUBLE_EQ(r.auc, 0.8);

  TrackEvalOptions o;
  o.lost_is_failure = true;
  EXPECT_DOUBLE_EQ(evaluate_tracks(truth, est, o).failure_rate, 0.6);
}

TEST(TrackMetrics, InvisibleTruthIsNotScoredAndExtraFramesAreCounted) {
  auto truth = truth_sequence(3);
  truth[1].markers[2].valid = false;                 // occluded in the truth: no error, not lost
  for (auto& m : truth[2].markers) m.valid = false;  // nothing visible: frame not scored
  auto est = truth;
  est[1].markers[2].position = {1000, 1000};
  est.push_back(truth_frame(7));
  const TrackEvalResult r = evaluate_tracks(truth, est);
  EXPECT_EQ(r.scored_frames, 2);
  EXPECT_EQ(r.extra_frames, 1);
  EXPECT_EQ(r.lost_observations, 0);
  EXPECT_DOUBLE_EQ(r.nme.max, 0.0);
}

TEST(TrackMetrics, AnInvisibleEyeCornerFallsBackToTheMedianDistance) {
  auto truth = truth_sequence(4);
  truth[3].markers[1].valid = false;
  auto est = truth;
  for (auto& m : est[3].markers) m.position += cv::Point2d(0, 10);
  const TrackEvalResult r = evaluate_tracks(truth, est);
  EXPECT_EQ(r.norm_fallback_frames, 1);
  EXPECT_TRUE(r.frames[3].norm_fallback);
  EXPECT_NEAR(r.frames[3].nme, 0.1, 1e-12);
}

TEST(TrackMetrics, MatchingByFeaturePoint) {
  const auto truth = truth_sequence(2);
  auto est = truth;
  for (auto& f : est)
    for (auto& m : f.markers) m.marker = "other_" + m.marker;
  // By marker id the two share nothing: an error, not a score of everything lost.
  EXPECT_THROW(evaluate_tracks(truth, est), InputError);
  TrackEvalOptions o;
  o.match = MatchBy::FeaturePoint;
  const TrackEvalResult r = evaluate_tracks(truth, est, o);
  EXPECT_EQ(r.lost_observations, 0);
  EXPECT_EQ(r.scored_observations, 8);
}

TEST(TrackMetrics, MarkersWithoutAFeaturePointAreLeftOutOfFeaturePointMatching) {
  auto truth = truth_sequence(2);
  auto est = truth;
  for (auto& f : est)
    for (const char* tag : {"tag36h11:0", "tag36h11:1"}) {
      MarkerObservation t;  // a headband tag: no feature point
      t.marker = tag;
      t.position = {300, 50};
      t.valid = true;
      f.markers.push_back(t);
    }
  TrackEvalOptions o;
  o.match = MatchBy::FeaturePoint;
  const TrackEvalResult r = evaluate_tracks(truth, est, o);
  EXPECT_EQ(r.scored_observations, 8);
  EXPECT_EQ(r.markers.size(), 4u);
}

TEST(TrackMetrics, BadInputIsAnInputError) {
  auto truth = truth_sequence(2);
  auto est = truth;
  TrackEvalOptions o;
  o.norm_a = "9.3";  // no such marker in the truth
  EXPECT_THROW(evaluate_tracks(truth, est, o), InputError);
  auto repeated = est;
  repeated[1].frame = 0;
  EXPECT_THROW(evaluate_tracks(truth, repeated), InputError);
  auto twice = est;
  twice[0].markers.push_back(twice[0].markers[0]);
  EXPECT_THROW(evaluate_tracks(truth, twice), InputError);
}

}  // namespace
}  // namespace rostro::eval
