// The tracker on synthetic takes with exact truth: accuracy, identification, occlusions,
// identities, and AprilTag corners drawn from their bit patterns.

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <opencv2/imgproc.hpp>
#include <set>

#include "facecore/error.hpp"
#include "tests/support/synthetic_scene.hpp"
#include "tracking/apriltag_detector.hpp"
#include "tracking/identify.hpp"
#include "tracking/layout.hpp"
#include "tracking/marker_tracker.hpp"
#include "tracking/name_corrections.hpp"
#include "tracking/start_backfill.hpp"
#include "tracking/tracks_csv.hpp"

namespace fs = std::filesystem;
using namespace rostro::tracking;
using rostro::tracking::testing::Occluder;
using rostro::tracking::testing::SceneOptions;
using rostro::tracking::testing::SyntheticScene;
using rostro::tracking::testing::Truth;

namespace {

MarkerLayout default_layout() {
  return load_layout(fs::path(ROSTRO_DATA_DIR) / "layouts" / "default.json");
}

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[static_cast<size_t>(q * static_cast<double>(v.size() - 1))];
}

struct RunStats {
  std::vector<double> errors;  // valid, fully visible dots
  long visible = 0, valid_visible = 0;
  long guessed = 0;  // valid while hidden under an occluder
  long off = 0;      // valid while partly covered, but more than 1 px from the truth
  long swaps = 0;    // valid but nearer another marker's truth than its own
  long late = 0;     // visible for 3+ frames after an occlusion, still invalid
};

// The synthetic scene is a skin texture, not a face: identification goes by the layout's
// arrangement alone (IdentifiesOnlyOnAFaceWhenTheModelIsThere).
TrackerOptions options_for(const SceneOptions& scene) {
  TrackerOptions o;
  o.identification.face_model.clear();
  o.dots.min_diameter_px = std::max(3.0, scene.dot_diameter_px * 0.5);
  o.dots.max_diameter_px = scene.dot_diameter_px * 2;
  o.tags.decimation = 1;
  return o;
}

RunStats run(const MarkerLayout& layout, const SceneOptions& scene_options, int frames,
             MarkerTracker* given = nullptr) {
  SyntheticScene scene(layout, scene_options);
  MarkerTracker own(layout, options_for(scene_options));
  MarkerTracker& tracker = given ? *given : own;
  RunStats st;
  std::map<std::string, int> visible_run;  // consecutive visible frames per marker
  for (int k = 0; k < frames; ++k) {
    std::map<std::string, Truth> truth;
    cv::Mat image = scene.render(k, truth);
    TrackedFrame tf = tracker.track(image, k, k / 30.0);
    EXPECT_EQ(tf.markers.size(), layout.markers.size());
    for (const MarkerObservation& m : tf.markers) {
      auto it = truth.find(m.marker);
      if (it == truth.end()) continue;
      const Truth& tr = it->second;
      int& run_length = visible_run[m.marker];
      run_length = tr.visible ? run_length + 1 : 0;
      const bool is_tag = layout.find(m.marker)->is_tag();
      if (m.valid && tr.hidden) {
        ++st.guessed;
        ADD_FAILURE() << "frame " << k << ": " << m.marker << " valid while hidden";
      }
      if (m.valid && !tr.visible && !tr.hidden && cv::norm(m.position - tr.position) > 1) {
        ++st.off;
        ADD_FAILURE() << "frame " << k << ": " << m.marker << " partly covered and "
                      << cv::norm(m.position - tr.position) << " px off";
      }
      if (m.valid) {
        const double own_error = cv::norm(m.position - tr.position);
        for (const auto& [other, otr] : truth)
          if (other != m.marker && cv::norm(m.position - otr.position) < own_error) {
            ++st.swaps;
            ADD_FAILURE() << "frame " << k << ": " << m.marker << " sits on " << other;
            break;
          }
      }
      if (!tr.visible || is_tag) continue;
      ++st.visible;
      if (m.valid) {
        ++st.valid_visible;
        st.errors.push_back(cv::norm(m.position - tr.position));
      } else if (run_length > 3 && k > 3) {
        ++st.late;
        ADD_FAILURE() << "frame " << k << ": " << m.marker << " visible for " << run_length
                      << " frames but not re-acquired";
      }
    }
  }
  return st;
}

// 10 px dots that do not move but for the scene's slow roll and scale, so that an occluder's
// edge can be placed against one.
SceneOptions still_dots() {
  SceneOptions o;
  o.motion_px = 0, o.expression_px = 0;
  o.dot_diameter_px = 10;
  return o;
}

// One marker in one frame: as tracked (reported or not, its state after the frame) and as drawn.
struct OneMarker {
  bool reported = false;
  cv::Point2d at;  // when reported
  bool held = false;
  LostReason lost_reason = LostReason::None;
  Truth truth;
};

// Marker `id` in frames 0 to `last` of `scene_options` tracked with `options`.
std::vector<OneMarker> follow_one(const MarkerLayout& layout, const SceneOptions& scene_options,
                                  const TrackerOptions& options, int last, const std::string& id) {
  SyntheticScene scene(layout, scene_options);
  MarkerTracker tracker(layout, options);
  std::vector<OneMarker> frames;
  for (int k = 0; k <= last; ++k) {
    std::map<std::string, Truth> truth;
    const TrackedFrame tf = tracker.track(scene.render(k, truth), k, k / 30.0);
    OneMarker one;
    one.truth = truth.at(id);
    for (const MarkerObservation& m : tf.markers)
      if (m.marker == id) one.reported = m.valid, one.at = m.position;
    for (const MarkerState& st : tracker.states())
      if (st.spec->id == id) one.held = st.held, one.lost_reason = st.lost_reason;
    frames.push_back(one);
  }
  return frames;
}

}  // namespace

class DotAccuracy : public ::testing::TestWithParam<double> {};

TEST_P(DotAccuracy, MedianAndTailErrorWithinBudget) {
  MarkerLayout layout = default_layout();
  SceneOptions o;
  o.dot_diameter_px = GetParam();
  RunStats st = run(layout, o, 60);
  ASSERT_GT(st.visible, 0);
  EXPECT_GE(static_cast<double>(st.valid_visible), 0.98 * static_cast<double>(st.visible));
  const double median = percentile(st.errors, 0.5), p95 = percentile(st.errors, 0.95);
  RecordProperty("median_px", std::to_string(median));
  RecordProperty("p95_px", std::to_string(p95));
  std::printf("dots %.0f px: median %.3f px, 95th percentile %.3f px, %ld/%ld valid\n", GetParam(),
              median, p95, st.valid_visible, st.visible);
  EXPECT_LE(median, 0.2);
  EXPECT_LE(p95, 0.5);
  EXPECT_EQ(st.swaps, 0);
}

INSTANTIATE_TEST_SUITE_P(Diameters, DotAccuracy, ::testing::Values(6.0, 8.0, 12.0));

TEST(Tracker, OcclusionsAreFlaggedAndMarkersComeBack) {
  MarkerLayout layout = default_layout();
  SceneOptions o;
  o.noise_sigma = 3;
  o.blur_sigma = 1.0;
  // A hand over the mouth, then one over the left brow and eye, then a bar across the face.
  o.occluders = {
      {{330, 300, 90, 60}, 10, 19}, {{340, 180, 70, 60}, 25, 31}, {{150, 260, 340, 25}, 38, 40}};
  RunStats st = run(layout, o, 50);
  EXPECT_EQ(st.guessed, 0);
  EXPECT_EQ(st.off, 0);
  EXPECT_EQ(st.late, 0);
  EXPECT_EQ(st.swaps, 0);
  EXPECT_LE(percentile(st.errors, 0.5), 0.2);
}

// A hand over a headband tag: the tag is dropped while hidden (its pattern no longer fits where
// LK puts its corners, and it is not detected there), never reported off its place while partly
// covered, and back within 3 frames of coming out. The tags' places come from a first run.
TEST(Tracker, AHiddenTagIsDroppedAndComesBack) {
  MarkerLayout layout = default_layout();
  SceneOptions o;
  std::map<std::string, Truth> start;
  SyntheticScene(layout, o).render(12, start);
  const Truth& tag = start.at("tag36h11:1");
  double x0 = 1e9, y0 = 1e9, x1 = -1e9, y1 = -1e9;
  for (const cv::Point2d& c : tag.corners)
    x0 = std::min(x0, c.x), y0 = std::min(y0, c.y), x1 = std::max(x1, c.x), y1 = std::max(y1, c.y);
  const double pad = (x1 - x0) / 3 + o.motion_px + 2;
  // Wholly over it on frames 10-19, then over its left third or so on frames 25-29.
  o.occluders = {{{x0 - pad, y0 - pad, x1 - x0 + 2 * pad, y1 - y0 + 2 * pad}, 10, 19},
                 {{x0 - pad, y0 - pad, 0.3 * (x1 - x0) + pad, y1 - y0 + 2 * pad}, 25, 29}};
  SyntheticScene scene(layout, o);
  MarkerTracker tracker(layout, options_for(o));
  int back_at = -1, back_after_partial = -1;
  for (int k = 0; k < 40; ++k) {
    std::map<std::string, Truth> truth;
    const TrackedFrame tf = tracker.track(scene.render(k, truth), k, k / 30.0);
    const Truth& t = truth.at("tag36h11:1");
    for (const MarkerObservation& m : tf.markers) {
      if (m.marker != "tag36h11:1") continue;
      if (k >= 10 && k <= 19) {
        EXPECT_FALSE(m.valid) << "frame " << k << ": valid while hidden";
      }
      if (m.valid) {
        EXPECT_LT(cv::norm(m.position - t.position), 1.0) << "frame " << k;
      }
      if (k > 19 && k < 25 && m.valid && back_at < 0) back_at = k;
      if (k > 29 && m.valid && back_after_partial < 0) back_after_partial = k;
    }
  }
  EXPECT_GE(back_at, 20);
  EXPECT_LE(back_at, 22) << "the tag was not back within 3 frames of the hand leaving it";
  EXPECT_GE(back_after_partial, 30);
  EXPECT_LE(back_after_partial, 32);
}

// Every invalid marker names the rule that dropped it (or that it was never identified), a
// valid one none; the dots under a hand are dropped by a rule, not left unidentified.
TEST(Tracker, EveryLostMarkerNamesTheRuleThatDroppedIt) {
  MarkerLayout layout = default_layout();
  SceneOptions o;
  o.occluders = {{{330, 300, 90, 60}, 10, 19}};
  SyntheticScene scene(layout, o);
  MarkerTracker tracker(layout, options_for(o));
  for (const MarkerState& s : tracker.states())
    EXPECT_EQ(s.lost_reason, LostReason::Unidentified) << s.spec->id;
  long hidden = 0;
  for (int k = 0; k < 20; ++k) {
    std::map<std::string, Truth> truth;
    cv::Mat image = scene.render(k, truth);
    tracker.track(image, k, k / 30.0);
    for (const MarkerState& s : tracker.states()) {
      EXPECT_EQ(s.valid, s.lost_reason == LostReason::None)
          << "frame " << k << ": " << s.spec->id << " " << to_string(s.lost_reason);
      if (!truth.at(s.spec->id).hidden) continue;
      ++hidden;
      EXPECT_NE(s.lost_reason, LostReason::None) << "frame " << k << ": " << s.spec->id;
      EXPECT_NE(s.lost_reason, LostReason::Unidentified) << "frame " << k << ": " << s.spec->id;
    }
  }
  EXPECT_GT(hidden, 0);
}

// A frame where the following keeps fewer markers than a start needs (most of the face
// covered at once, or a motion past LK's reach) gives none of them: with nothing beside them
// they are checked against nothing, and one that slid onto a neighbour's dot looks as sure as
// one that kept its own. The face is identified afresh once it is seen again.
TEST(Tracker, AFrameKeepingFewerMarkersThanAStartNeedsGivesNone) {
  const MarkerLayout layout = default_layout();
  SceneOptions o;
  o.motion_px = 0, o.expression_px = 0;  // still dots, so what the cover leaves is known
  std::map<std::string, Truth> at_rest;
  SyntheticScene(layout, o).render(0, at_rest);
  // Frame 10 covered above a line between the second and third lowest markers: two left.
  std::vector<double> ys;
  for (const auto& [id, t] : at_rest) ys.push_back(t.position.y);
  std::sort(ys.rbegin(), ys.rend());
  const double cut = (ys[1] + ys[2]) / 2;
  o.occluders = {{{0, 0, static_cast<double>(o.size.width), cut}, 10, 10}};
  SyntheticScene scene(layout, o);
  MarkerTracker tracker(layout, options_for(o));
  int back_at = -1;
  for (int k = 0; k < 16; ++k) {
    std::map<std::string, Truth> truth;
    const TrackedFrame tf = tracker.track(scene.render(k, truth), k, k / 30.0);
    long valid = 0, visible = 0;
    for (const MarkerObservation& m : tf.markers) valid += m.valid;
    for (const auto& [id, t] : truth) visible += !t.hidden;
    if (k < 10) {
      EXPECT_EQ(valid, static_cast<long>(tf.markers.size())) << "frame " << k;
    } else if (k == 10) {
      ASSERT_EQ(visible, 2) << "the cover should leave two markers in sight";
      EXPECT_EQ(valid, 0) << "frame 10 gave markers it could check against nothing";
      long too_few = 0;
      for (const MarkerState& s : tracker.states()) too_few += s.lost_reason == LostReason::TooFew;
      EXPECT_GE(too_few, 1) << "no marker followed into frame 10 was dropped as one of too few";
    } else if (back_at < 0 && valid == static_cast<long>(tf.markers.size())) {
      back_at = k;
    }
  }
  EXPECT_EQ(back_at, 11) << "not identified afresh on the first frame seen whole again";
}

// An edge that cuts into a followed dot (a hand arriving) shrinks its blob and pulls its
// centre away from the bite: the dot is dropped for those frames (min_recent_size), where
// without the rule it is reported off its place.
TEST(Tracker, ADotAnEdgeCutsIntoIsDroppedNotReportedOffItsPlace) {
  const MarkerLayout layout = default_layout();
  SceneOptions o = still_dots();
  std::map<std::string, Truth> at_rest;
  SyntheticScene(layout, o).render(0, at_rest);
  const cv::Point2d dot = at_rest.at("cheek_l").position;
  // The occluder's left edge 0.15 of a diameter right of the centre: a third of the dot covered.
  o.occluders = {{{dot.x + 0.15 * o.dot_diameter_px, dot.y - 20, 40, 40}, 10, 12}};
  struct Seen {
    int dropped_as_shrunk = 0, reported = 0;
    double worst_px = 0;
  };
  auto follow = [&](double min_recent_size) {
    TrackerOptions options = options_for(o);
    options.min_recent_size = min_recent_size;
    const std::vector<OneMarker> frames = follow_one(layout, o, options, 12, "cheek_l");
    Seen seen;
    for (int k = 10; k <= 12; ++k) {
      const OneMarker& f = frames[static_cast<size_t>(k)];
      EXPECT_FALSE(f.truth.visible) << "frame " << k;
      EXPECT_FALSE(f.truth.hidden) << "frame " << k;
      seen.dropped_as_shrunk += f.lost_reason == LostReason::Shrunk;
      if (f.reported) {
        ++seen.reported;
        seen.worst_px = std::max(seen.worst_px, cv::norm(f.at - dot));
      }
    }
    return seen;
  };
  const Seen with_rule = follow(TrackerOptions().min_recent_size);
  EXPECT_EQ(with_rule.reported, 0);
  EXPECT_EQ(with_rule.dropped_as_shrunk, 3);
  const Seen without = follow(0);
  std::printf("cut into by an edge, the dot reported up to %.2f px off without the rule\n",
              without.worst_px);
  EXPECT_EQ(without.reported, 3);
  EXPECT_GT(without.worst_px, 0.5);
}

// A dot under a hand for ten frames, whose edge then draws back past it in two steps: on the
// first frame out, the edge still cuts a sliver (a tenth of its width) off it. Found again
// there, it is followed from that frame and reported from the next, where it is whole
// (hold_found_after_lost); reported at once, it is reported off its place. (A deeper cut fails
// the checks a dot is found again by, its size and look.)
TEST(Tracker, ADotComingOutFromUnderAnEdgeIsReportedFromItsNextFrame) {
  const MarkerLayout layout = default_layout();
  SceneOptions o = still_dots();
  // Where the dot is on frame 20: the scene's slow roll and scale still move it a few pixels.
  std::map<std::string, Truth> out;
  SyntheticScene(layout, o).render(20, out);
  const cv::Point2d dot = out.at("cheek_l").position;
  o.occluders = {{{dot.x - 20, dot.y - 20, 40, 40}, 10, 19},
                 {{dot.x + 0.4 * o.dot_diameter_px, dot.y - 20, 40, 40}, 20, 20}};
  struct Seen {
    std::vector<int> reported_from;  // frames from 10 on with cheek_l reported
    bool held_on_20 = false;
    double worst_px = 0;
  };
  auto follow = [&](int hold_found_after_lost) {
    TrackerOptions options = options_for(o);
    options.hold_found_after_lost = hold_found_after_lost;
    const std::vector<OneMarker> frames = follow_one(layout, o, options, 24, "cheek_l");
    Seen seen;
    seen.held_on_20 = frames[20].held && frames[20].lost_reason == LostReason::FoundAgain;
    for (int k = 10; k <= 24; ++k) {
      const OneMarker& f = frames[static_cast<size_t>(k)];
      if (!f.reported) continue;
      seen.reported_from.push_back(k);
      seen.worst_px = std::max(seen.worst_px, cv::norm(f.at - f.truth.position));
    }
    return seen;
  };
  const Seen held = follow(TrackerOptions().hold_found_after_lost);
  ASSERT_FALSE(held.reported_from.empty());
  EXPECT_EQ(held.reported_from.front(), 21);
  EXPECT_EQ(held.reported_from.size(), 4u);  // 21-24
  EXPECT_TRUE(held.held_on_20);
  EXPECT_LT(held.worst_px, 0.1);
  const Seen at_once = follow(0);
  std::printf(
      "coming out from under the edge, reported at once: from frame %d, up to %.2f px off\n",
      at_once.reported_from.empty() ? -1 : at_once.reported_from.front(), at_once.worst_px);
  ASSERT_FALSE(at_once.reported_from.empty());
  EXPECT_EQ(at_once.reported_from.front(), 20);
  EXPECT_GT(at_once.worst_px, 0.3);
}

// A dot under a hand from the start, and on the hand near its place a smaller dark speck (a
// freckle, a hair; at the mouth, its corner): the dot was never measured, and the speck is
// smaller than the size it was given at the start, the other dots' size, by more than a dot
// shrinks in a frame (min_recent_size). It is not taken as the dot. (The second look is off:
// it places names on the dots of a fresh naming by their look, not their size; judged by size
// there too, the blurred starts of the held-out photo scenes lost 670 more observations.)
TEST(Tracker, ADotNeverSeenIsNotFoundOnASmallerSpeck) {
  const MarkerLayout layout = default_layout();
  SceneOptions o = still_dots();
  std::map<std::string, Truth> at_rest;
  SyntheticScene(layout, o).render(0, at_rest);
  const cv::Point2d dot = at_rest.at("cheek_l").position;
  o.occluders = {{{dot.x - 20, dot.y - 20, 40, 40}, 0, 30}};
  const int speck_radius_px = 3;
  auto reported = [&](double min_recent_size) {
    TrackerOptions options = options_for(o);
    options.min_recent_size = min_recent_size;
    options.second_look_after = 0;
    SyntheticScene scene(layout, o);
    MarkerTracker tracker(layout, options);
    int frames = 0;
    for (int k = 0; k <= 30; ++k) {
      std::map<std::string, Truth> truth;
      cv::Mat image = scene.render(k, truth);
      EXPECT_TRUE(truth.at("cheek_l").hidden) << "frame " << k;
      if (k >= 3)  // from the third frame, 3 px beside where the dot is
        cv::circle(image, cv::Point(dot + cv::Point2d(3, 0)), speck_radius_px, cv::Scalar(40),
                   cv::FILLED, cv::LINE_AA);
      const TrackedFrame tf = tracker.track(image, k, k / 30.0);
      for (const MarkerObservation& m : tf.markers) frames += m.marker == "cheek_l" && m.valid;
    }
    return frames;
  };
  const int with_rule = reported(TrackerOptions().min_recent_size);
  const int without = reported(0);
  std::printf(
      "a speck where a dot never seen should be: taken as the dot in %d of 31 frames (%d "
      "without the rule)\n",
      with_rule, without);
  EXPECT_EQ(with_rule, 0);
  EXPECT_GT(without, 0);
}

// A take whose tags are read only from frame 8 (covered before): the tracker starts there, and
// the frames before it, held, are filled by following the dots back from it: each within a
// pixel of its own dot, where without the filling every marker was invalid.
TEST(StartBackfill, TheFramesBeforeTheStartAreFollowedBackFromIt) {
  const MarkerLayout layout = default_layout();
  SceneOptions o;
  std::map<std::string, Truth> first;
  SyntheticScene(layout, o).render(0, first);
  for (const MarkerSpec& m : layout.markers) {
    if (!m.is_tag()) continue;
    double x0 = 1e9, y0 = 1e9, x1 = -1e9, y1 = -1e9;
    for (const cv::Point2d& c : first.at(m.id).corners)
      x0 = std::min(x0, c.x), y0 = std::min(y0, c.y), x1 = std::max(x1, c.x),
      y1 = std::max(y1, c.y);
    const double pad = o.motion_px + 4;
    o.occluders.push_back({{x0 - pad, y0 - pad, x1 - x0 + 2 * pad, y1 - y0 + 2 * pad}, 0, 7});
  }
  SyntheticScene scene(layout, o);
  MarkerTracker tracker(layout, options_for(o));
  StartBackfill backfill(tracker, tracker.correction_horizon());
  std::vector<TrackedFrame> take;
  std::vector<std::map<std::string, Truth>> truths;
  long made_valid = 0;
  for (int k = 0; k < 14; ++k) {
    truths.emplace_back();
    const cv::Mat image = scene.render(k, truths.back());
    TrackedFrame now = tracker.track(image, k, k / 30.0);
    made_valid += backfill.take(now, take, image);
    append_corrected(take, std::move(now));
  }
  const long started_on = backfill.started_at(), filled_from = backfill.filled_from();
  ASSERT_EQ(started_on, 8) << "the start waits for the hidden tag";
  EXPECT_EQ(filled_from, 0);
  long filled = 0;
  for (long k = 0; k < started_on; ++k)
    for (const MarkerObservation& m : take[static_cast<size_t>(k)].markers) {
      if (!m.valid || layout.find(m.marker)->is_tag()) continue;
      ++filled;
      EXPECT_LT(cv::norm(m.position - truths[static_cast<size_t>(k)].at(m.marker).position), 1.0)
          << "frame " << k << ": " << m.marker;
    }
  EXPECT_EQ(filled, made_valid);
  EXPECT_GT(filled, 8 * 25) << "most dots of the 8 frames";
}

TEST(Tracker, EachLostReasonHasItsOwnName) {
  std::set<std::string> names;
  for (int k = 0; k < kLostReasonCount; ++k) names.insert(to_string(static_cast<LostReason>(k)));
  EXPECT_EQ(names.size(), static_cast<size_t>(kLostReasonCount));
  EXPECT_STREQ(to_string(LostReason::TooFew), "too few");
}

// A layout of dots alone is identified by the dots' arrangement; one with tags waits for them
// (IdentifiesOnlyWhenItsTagsAreRead).
TEST(Tracker, IdentifiesWithoutTagsAndWhenTurned) {
  const MarkerLayout with_tags = default_layout();
  MarkerLayout dots_only = with_tags;
  std::erase_if(dots_only.markers, [](const MarkerSpec& m) { return m.is_tag(); });
  for (bool tags : {true, false})
    for (double angle : {-12.0, 0.0, 15.0}) {
      const MarkerLayout& layout = tags ? with_tags : dots_only;
      SceneOptions o;
      o.draw_tags = tags;
      o.angle_deg = angle;
      SyntheticScene scene(layout, o);
      std::map<std::string, Truth> truth;
      cv::Mat image = scene.render(0, truth);
      MarkerTracker tracker(layout, options_for(o));
      TrackedFrame tf = tracker.track(image, 0, 0);
      for (const MarkerObservation& m : tf.markers) {
        if (!truth.count(m.marker)) continue;
        EXPECT_TRUE(m.valid) << m.marker << " tags " << tags << " angle " << angle;
        if (m.valid) {
          EXPECT_LT(cv::norm(m.position - truth[m.marker].position), 1.0) << m.marker;
        }
      }
    }
}

// Without its tags a layout's dots alone can be named a row off (a real face's pupils and
// nostrils fill the gaps): the tracker does not start, and says why.
TEST(Tracker, IdentifiesOnlyWhenItsTagsAreRead) {
  MarkerLayout layout = default_layout();
  SceneOptions o;
  o.draw_tags = false;
  SyntheticScene scene(layout, o);
  std::map<std::string, Truth> truth;
  MarkerTracker tracker(layout, options_for(o));
  const TrackedFrame tf = tracker.track(scene.render(0, truth), 0, 0);
  EXPECT_FALSE(tracker.started());
  for (const MarkerObservation& m : tf.markers) EXPECT_FALSE(m.valid) << m.marker;
  EXPECT_FALSE(tracker.identification().confident);
  EXPECT_EQ(tracker.identification().doubt, "0 of 3 tags read");
  EXPECT_EQ(tracker.started_at(), -1);

  // The same scene with its tags starts, and says so on its first frame.
  o.draw_tags = true;
  SyntheticScene tagged(layout, o);
  MarkerTracker second(layout, options_for(o));
  const TrackedFrame first = second.track(tagged.render(0, truth), 7, 0);
  EXPECT_TRUE(second.started());
  EXPECT_EQ(second.started_at(), 7);
  EXPECT_TRUE(second.identification().confident);
  EXPECT_EQ(second.identification().tags_seen, 3);
  EXPECT_NE(first.identification.find("identified, "), std::string::npos) << first.identification;
}

// With dlib's landmark model at hand, markers are named only on a frame where it finds the
// face they are on: the textured scene has none.
TEST(Tracker, IdentifiesOnlyOnAFaceWhenTheModelIsThere) {
  if (!std::filesystem::exists(default_landmark_model()))
    GTEST_SKIP() << "no landmark model at " << default_landmark_model() << " (libdlib-data)";
  MarkerLayout layout = default_layout();
  SceneOptions o;
  SyntheticScene scene(layout, o);
  std::map<std::string, Truth> truth;
  TrackerOptions options = options_for(o);
  options.identification.face_model = default_landmark_model();
  MarkerTracker tracker(layout, options);
  tracker.track(scene.render(0, truth), 0, 0);
  EXPECT_FALSE(tracker.started());
  EXPECT_EQ(tracker.identification().doubt, "the landmark model found no face");
}

TEST(Tracker, StartsFromAFileOfPositions) {
  MarkerLayout layout = default_layout();
  SceneOptions o;
  SyntheticScene scene(layout, o);
  std::map<std::string, Truth> truth;
  scene.render(0, truth);
  // Rough clicks (1.5 px off) for every dot, in the tracks CSV format.
  TrackedFrame start;
  int n = 0;
  for (const MarkerSpec& m : layout.markers) {
    if (m.is_tag()) continue;
    cv::Point2d jitter((n % 3 - 1) * 1.5, (n % 2) * 1.5 - 0.75);
    start.markers.push_back({m.id, m.feature_point, truth[m.id].position + jitter, true, 1});
    ++n;
  }
  fs::path p = fs::temp_directory_path() / "rostro_start_positions.csv";
  write_tracks(p, {start});
  MarkerTracker tracker(layout, options_for(o));
  tracker.set_start_positions(read_start_positions(p, layout));
  RunStats st = run(layout, o, 10, &tracker);
  EXPECT_GE(static_cast<double>(st.valid_visible), 0.98 * static_cast<double>(st.visible));
  EXPECT_LE(percentile(st.errors, 0.5), 0.2);
}

TEST(AprilTagSynthetic, CornersFromBitPatternsInLibapriltagOrder) {
  MarkerLayout layout = default_layout();
  SceneOptions o;
  o.angle_deg = 20;
  SyntheticScene scene(layout, o);
  std::map<std::string, Truth> truth;
  cv::Mat image = scene.render(3, truth);
  AprilTagOptions ao;
  ao.decimation = 1;
  AprilTagDetector detector(ao);
  auto found = detector.detect(image);
  int matched = 0;
  for (const MarkerSpec& m : layout.markers) {
    if (!m.is_tag()) continue;
    for (const TagDetection& t : found) {
      if (t.marker_id() != m.id) continue;
      ++matched;
      for (int k = 0; k < 4; ++k)
        EXPECT_LT(cv::norm(t.corners[k] - truth[m.id].corners[k]), 0.5) << m.id << " corner " << k;
    }
  }
  EXPECT_EQ(matched, layout.tag_count());
}

TEST(AprilTagImage, BitPatternHasTheFamilyWidth) {
  cv::Mat tag = apriltag_image("tag36h11", 5);
  EXPECT_EQ(tag.cols, 10);
  EXPECT_EQ(apriltag_black_width("tag36h11"), 8);
  EXPECT_EQ(tag.at<uint8_t>(0, 0), 255);  // white border
  EXPECT_EQ(tag.at<uint8_t>(1, 1), 0);    // black border
  EXPECT_THROW(apriltag_image("tag36h11", 100000), rostro::InputError);
  EXPECT_THROW(apriltag_image("tag99", 0), rostro::InputError);
}
