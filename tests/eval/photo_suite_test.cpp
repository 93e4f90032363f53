// The photo scenes file (data/eval/photo_scenes.json), the counts `rostro eval photos` adds
// to the suite's columns (markers reported while hidden, frames to reacquire), and what a
// scenario's run keeps for `--out`.

#include "eval/photo_suite.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <span>
#include <sstream>
#include <stdexcept>

#include "eval/report.hpp"
#include "eval/track_metrics.hpp"
#include "facecore/error.hpp"

namespace rostro::eval {
namespace {

// Frames of one marker "m": visible[i] in the truth; reported[i] valid in the estimate at
// `offset` px from the truth.
void make(const std::vector<bool>& visible, const std::vector<bool>& reported, double offset,
          std::vector<tracking::TrackedFrame>& truth, std::vector<tracking::TrackedFrame>& est) {
  for (std::size_t i = 0; i < visible.size(); ++i) {
    tracking::TrackedFrame t, e;
    t.frame = e.frame = static_cast<long>(i);
    t.markers.push_back({"m", {}, {100, 100}, visible[i], 1});
    e.markers.push_back({"m", {}, {100 + offset, 100}, reported[i], 1});
    truth.push_back(t);
    est.push_back(e);
  }
}

TEST(PhotoSuite, CountsHiddenButReportedAndFramesToReacquire) {
  std::vector<tracking::TrackedFrame> truth, est;
  //            0     1     2      3      4     5      6      7     8
  make({true, true, false, false, true, true, true, true, true},
       {true, true, true, false, false, false, true, true, true}, 0.5, truth, est);
  PhotoRow row;
  count_hidden_and_reacquire(truth, est, row);
  EXPECT_EQ(row.hidden_reported, 1);  // frame 2
  EXPECT_EQ(row.occlusions, 1);
  EXPECT_EQ(row.worst_reacquire, 2);  // back in view at 4, reported at 6
}

TEST(PhotoSuite, AMarkerReportedFarFromItsTruthIsNotBack) {
  std::vector<tracking::TrackedFrame> truth, est;
  make({true, false, true, true}, {true, false, true, true}, 5.0, truth, est);
  PhotoRow row;
  count_hidden_and_reacquire(truth, est, row);
  EXPECT_EQ(row.worst_reacquire, -1);
}

TEST(PhotoSuite, HiddenFromTheStartIsNoOcclusion) {
  std::vector<tracking::TrackedFrame> truth, est;
  make({false, false, true, true}, {false, true, true, true}, 0.0, truth, est);
  PhotoRow row;
  count_hidden_and_reacquire(truth, est, row);
  EXPECT_EQ(row.hidden_reported, 1);
  EXPECT_EQ(row.occlusions, 0);
  EXPECT_EQ(row.worst_reacquire, 0);
}

TEST(PhotoSuite, TheReportCarriesEveryFigureOfTheTables) {
  std::vector<tracking::TrackedFrame> truth, est;
  make({true, false, true, true}, {true, true, true, true}, 5.0, truth, est);
  PhotoRow row;
  row.suite.name = "hand_a";
  row.suite.title = "a hand";
  row.suite.frames = 4;
  row.suite.result.scored_observations = 3;
  row.suite.result.lost_observations = 1;
  row.suite.result.swap_observations = 2;
  row.suite.result.astray_observations = 1;
  row.suite.result.error_px.median = 0.05;
  row.suite.result.error_px.p95 = 0.25;
  count_hidden_and_reacquire(truth, est, row);
  PhotoRow unscored;  // nothing visible: no error figures
  unscored.suite.name = "empty";

  const auto j = nlohmann::json::parse(
      photo_report_json({row, unscored}, "scenes.json", {"min_recent_size=0"}));
  EXPECT_EQ(j["kind"], "rostro.eval.photos");
  EXPECT_EQ(j["scenes"], "scenes.json");
  EXPECT_EQ(j["options"][0], "min_recent_size=0");
  ASSERT_EQ(j["rows"].size(), 2u);
  const auto& r = j["rows"][0];
  EXPECT_EQ(r["name"], "hand_a");
  EXPECT_EQ(r["title"], "a hand");
  EXPECT_DOUBLE_EQ(r["median_px"].get<double>(), 0.05);
  EXPECT_DOUBLE_EQ(r["p95_px"].get<double>(), 0.25);
  EXPECT_EQ(r["swapped"], 2);
  EXPECT_EQ(r["astray"], 1);
  EXPECT_EQ(r["lost"], 1);
  EXPECT_EQ(r["visible"], 4);
  EXPECT_EQ(r["hidden_reported"], 1);
  EXPECT_EQ(r["occlusions"], 1);
  EXPECT_TRUE(r["worst_reacquire"].is_null());  // 5 px off: never back
  EXPECT_TRUE(j["rows"][1]["median_px"].is_null());
  EXPECT_EQ(j["rows"][1]["worst_reacquire"], 0);
}

TEST(PhotoSuite, DefaultFileCoversEveryPhotoAndTheIssuesCases) {
  const PhotoSuiteDefinition d = load_photo_scenes(default_photo_scenes_path());
  std::set<std::string> photos;
  bool blur = false, enter = false, hand = false, vga = false;
  for (const PhotoScenario& s : d.scenarios) {
    photos.insert(s.scene.photo.string());
    blur = blur || s.scene.first_blur_px >= 14;
    enter = enter || s.scene.enter_seconds > 0;
    hand = hand || s.scene.hand;
    vga = vga || s.scene.size == cv::Size(640, 480);
    EXPECT_GE(s.scene.dot_px, 5) << s.name;
    EXPECT_LE(s.scene.dot_px, 14) << s.name;
  }
  EXPECT_EQ(photos, (std::set<std::string>{"2007_007763.jpg", "2008_001009.jpg", "2008_001322.jpg",
                                           "2008_002079.jpg", "bald_guys.jpg"}));
  EXPECT_TRUE(blur && enter && hand && vga);
}

TEST(PhotoSuite, ARunKeepsItsFramesTracksAndTruth) {
  const std::filesystem::path faces = default_faces_dir();
  if (!std::filesystem::is_directory(faces))
    GTEST_SKIP() << faces << " is absent (../shared beside the repository)";
  PhotoScenario s;
  s.name = "short";
  s.scene.photo = "bald_guys.jpg";
  s.scene.size = cv::Size(640, 480);
  s.scene.face_px = 200;
  s.scene.dot_px = 6;
  s.scene.seconds = 0.4;
  const tracking::MarkerLayout layout = tracking::load_layout(tracking::default_layout_path());
  long frames = 0;
  const PhotoRow row = run_photo_scenario(s, faces, layout, {}, {}, [&](const cv::Mat& bgr) {
    EXPECT_EQ(bgr.size(), cv::Size(640, 480));
    ++frames;
  });
  EXPECT_EQ(frames, 10);
  ASSERT_EQ(row.suite.tracks.size(), 10u);
  ASSERT_EQ(row.suite.truth.size(), 10u);
  EXPECT_EQ(row.suite.frames, 10);
  // Every layout marker in both, each frame; the tracker starts on a still, sharp face.
  const auto& first = row.suite.tracks.front().markers;
  EXPECT_TRUE(std::any_of(first.begin(), first.end(),
                          [](const tracking::MarkerObservation& m) { return m.valid; }));
  EXPECT_EQ(first.size(), row.suite.truth.front().markers.size());
}

// The scene of that name in a scenes file of data/eval/ (default: photo_scenes.json).
std::optional<PhotoScenario> default_scenario(const std::string& name,
                                              const std::string& file = "photo_scenes.json") {
  const PhotoSuiteDefinition d =
      load_photo_scenes(default_photo_scenes_path().parent_path() / file);
  for (const PhotoScenario& s : d.scenarios)
    if (s.name == name) return s;
  return std::nullopt;
}

// The head-turn scene (bald_guys.jpg) starts with its mouth-corner dots painted on the skin
// beside the lip corners, which dlib's landmarks mark; judged by place alone, identification
// named the dark lip corners instead and the take followed them.
TEST(PhotoSuite, HeadTurnsKeepTheMouthCornersOffTheLipCorners) {
  const std::filesystem::path faces = default_faces_dir();
  if (!std::filesystem::is_directory(faces))
    GTEST_SKIP() << faces << " is absent (../shared beside the repository)";
  const std::optional<PhotoScenario> scene = default_scenario("turns");
  ASSERT_TRUE(scene);
  PhotoScenario turns = *scene;
  turns.scene.seconds = 1;  // the swap was there from the first frame
  const tracking::MarkerLayout layout = tracking::load_layout(tracking::default_layout_path());
  const PhotoRow row = run_photo_scenario(turns, faces, layout);
  EXPECT_EQ(row.suite.result.swap_observations, 0);
  EXPECT_LT(row.suite.result.error_px.p95, 0.5);
  // The shape test is what keeps them: without it the lip corners are named.
  tracking::TrackerOptions any_shape;
  any_shape.identification.shape_factor = 100;
  const PhotoRow by_place = run_photo_scenario(turns, faces, layout, {}, any_shape);
  EXPECT_GT(by_place.suite.result.swap_observations, 0);
}

// The hand scene's face (2008_001009.jpg) starts with its three lower-lip dots unnamed (the middle
// one, in the lip's crease, is not detected). Their start places are then the identification's
// guesses; found together by the shape of those guesses, the middle name went on its right
// neighbour's dot on frame 3 and stayed there.
TEST(PhotoSuite, LowerLipDotsUnseenAtTheStartAreNotNamedOnANeighbour) {
  const std::filesystem::path faces = default_faces_dir();
  if (!std::filesystem::is_directory(faces))
    GTEST_SKIP() << faces << " is absent (../shared beside the repository)";
  const std::optional<PhotoScenario> scene = default_scenario("hand");
  ASSERT_TRUE(scene);
  PhotoScenario hand = *scene;
  hand.scene.seconds = 1.5;  // the swap was there from frame 3
  hand.scene.hand = false;   // the same face and talk, without the hand
  const tracking::MarkerLayout layout = tracking::load_layout(tracking::default_layout_path());
  const PhotoRow row = run_photo_scenario(hand, faces, layout);
  EXPECT_EQ(row.suite.result.swap_observations, 0);
}

// The default file's scene `name` tracked with `options`; nothing when ../shared is absent
// (the caller skips).
std::optional<PhotoRow> default_row(const std::string& name,
                                    const tracking::TrackerOptions& options = {}) {
  const std::filesystem::path faces = default_faces_dir();
  if (!std::filesystem::is_directory(faces)) return std::nullopt;
  const std::optional<PhotoScenario> scene = default_scenario(name);
  if (!scene) throw std::logic_error("no scene " + name);
  return run_photo_scenario(*scene, faces, tracking::load_layout(tracking::default_layout_path()),
                            {}, options);
}
std::string without_shared() {
  return default_faces_dir().string() + " is absent (../shared beside the repository)";
}

// Marker `id` in frame `f` (a default, invalid observation when the frame lacks it).
tracking::MarkerObservation at(const tracking::TrackedFrame& f, const std::string& id) {
  for (const tracking::MarkerObservation& m : f.markers)
    if (m.marker == id) return m;
  return {};
}

// The scenes of the next tests started with a wrong name while the face model's places were
// the dots' feature points themselves; each dot looked for `beside` its point, as the layout
// says it is worn (IdentificationOptions::dots_beside_points), they start right. The mechanisms
// that mend a wrong start are shown with that off.
tracking::TrackerOptions looked_for_at_points(tracking::TrackerOptions o = {}) {
  o.identification.dots_beside_points = false;
  return o;
}

// With the dots looked for at their points, the talk scene's face (bald_guys.jpg, the third
// face) starts with its middle lower-lip dot undetected and the name on its left neighbour's
// dot; LK follows a name wherever it starts.
// The identity check renames it once two checks in a row call it so, and every rename is
// right: the dot it moves is at its new name's place.
TEST(PhotoSuite, TheIdentityCheckRenamesAWrongStartingNameAndOnlyRightly) {
  const std::filesystem::path faces = default_faces_dir();
  if (!std::filesystem::is_directory(faces))
    GTEST_SKIP() << faces << " is absent (../shared beside the repository)";
  const std::optional<PhotoScenario> scene = default_scenario("talk");
  ASSERT_TRUE(scene);
  const tracking::MarkerLayout layout = tracking::load_layout(tracking::default_layout_path());
  const PhotoRow row = run_photo_scenario(*scene, faces, layout, {}, looked_for_at_points());
  int renames = 0;
  for (std::size_t k = 0; k < row.suite.tracks.size(); ++k) {
    const std::string& note = row.suite.tracks[k].identification;
    const std::string lead = "identities checked: renamed";
    if (note.rfind(lead, 0) != 0) continue;
    std::istringstream words(note.substr(lead.size()));
    std::string from, arrow, to;
    while (words >> from >> arrow >> to) {
      ++renames;
      const tracking::MarkerObservation tracked = at(row.suite.tracks[k], to);
      const tracking::MarkerObservation truth = at(row.suite.truth[k], to);
      ASSERT_TRUE(tracked.valid) << note;
      EXPECT_LT(cv::norm(tracked.position - truth.position), 2.0)
          << "frame " << k << ": " << from << " renamed " << to << " away from " << to << "'s dot";
    }
  }
  EXPECT_GE(renames, 1) << "the wrong starting name was never corrected";
  // From the rename on, no dot is followed under another's name.
  ASSERT_GE(row.suite.tracks.size(), 20u);
  EXPECT_EQ(
      evaluate_tracks(std::span(row.suite.truth).last(20), std::span(row.suite.tracks).last(20))
          .swap_observations,
      0);
}

// The talk scene as the tracker runs by default starts with the middle lower-lip dot
// undetected and its name on the left neighbour's dot; the second look, ten frames on, names
// them rightly and says what the renamed dot was since the start. Carried back
// (tracking/name_corrections.hpp), no frame of the take has a dot under another's name.
TEST(PhotoSuite, TheSecondLooksRenamesReachBackToTheStart) {
  const std::optional<PhotoRow> row = default_row("talk");
  if (!row) GTEST_SKIP() << without_shared();
  int corrected = 0;
  for (const tracking::TrackedFrame& f : row->suite.tracks)
    if (!f.corrections.empty()) {
      ++corrected;
      EXPECT_GE(f.corrected_since, 0);
      EXPECT_LT(f.corrected_since, f.frame);
    }
  EXPECT_GE(corrected, 1) << "the start was right: this scene no longer shows the carrying back";
  EXPECT_EQ(evaluate_tracks(row->suite.truth, row->suite.tracks).swap_observations, 0);
}

// The first 1.2 s (30 frames) of the default file's blurred scene `name`, tracked with
// `options`: the start on frame 2 and the second look on frame 12.
PhotoRow blurred_start(const std::string& name, const tracking::TrackerOptions& options = {}) {
  std::optional<PhotoScenario> scene = default_scenario(name);
  if (!scene) throw std::runtime_error("no scene " + name + " in the default file");
  scene->scene.seconds = 1.2;
  return run_photo_scenario(*scene, default_faces_dir(),
                            tracking::load_layout(tracking::default_layout_path()), {}, options);
}

// The last frame whose identification note begins with `lead`; -1 when none does.
long last_noted(const PhotoRow& row, const std::string& lead) {
  long at = -1;
  for (const tracking::TrackedFrame& f : row.suite.tracks)
    if (f.identification.rfind(lead, 0) == 0) at = f.frame;
  return at;
}

// Frames 13 to 13 + count - 1 (to the end when count is 0): after the second look.
std::span<const tracking::TrackedFrame> after_second_look(
    const std::vector<tracking::TrackedFrame>& frames, std::size_t count = 0) {
  return count ? std::span(frames).subspan(13, count) : std::span(frames).subspan(13);
}

TrackEvalResult after_second_look(const PhotoRow& row, std::size_t count = 0) {
  return evaluate_tracks(after_second_look(row.suite.truth, count),
                         after_second_look(row.suite.tracks, count));
}

tracking::TrackerOptions without_second_look() {
  tracking::TrackerOptions o;
  o.second_look_after = 0;
  return o;
}

// The second blurred scene (2008_001322.jpg, seed 2) starts on frame 2, still smeared by 8 px:
// the left mouth corner's dot, merged with the moustache's end, is not found, and the lip
// corner beside it takes its name. LK followed the lip corner to the end, near no other dot
// (astray, not a swap). The second look names the sharp frame 10 afresh and starts again.
TEST(PhotoSuite, ASmearedStartIsNamedAgainOnASharpFrame) {
  if (!std::filesystem::is_directory(default_faces_dir()))
    GTEST_SKIP() << default_faces_dir() << " is absent (../shared beside the repository)";
  const PhotoRow row = blurred_start("blur_seed2");
  EXPECT_EQ(last_noted(row, "identified again"), 12);  // 10 frames after the start
  ASSERT_EQ(row.suite.tracks.size(), 30u);
  EXPECT_EQ(after_second_look(row).astray_observations, 0);
  EXPECT_EQ(after_second_look(row).swap_observations, 0);
  // Without it, the lip corner keeps the name.
  EXPECT_GT(
      after_second_look(blurred_start("blur_seed2", without_second_look())).astray_observations,
      10);
}

// The held-out blurred start of seed 5 (2008_001322.jpg): the take starts on frame 2 with the
// left mouth corner's name on the lip corner, 25 px from its dot (merged with the moustache),
// sure for a wrong reason (margin 0.96: the blur washes out the rival dark features). The second
// look at frame 12 finds the rivals half back (margin 0.40, every name where it is followed); the
// looks at frames 22 and 32 both move the mouth corner's name to its dot, less sure than the
// start (0.71, 0.68) but two against one: the take starts again at frame 32.
TEST(PhotoSuite, TwoLessSureLooksThatAgreeOutvoteTheStart) {
  if (!std::filesystem::is_directory(default_faces_dir()))
    GTEST_SKIP() << default_faces_dir() << " is absent (../shared beside the repository)";
  std::optional<PhotoScenario> scene = default_scenario("blur_s5", "photo_scenes_heldout.json");
  ASSERT_TRUE(scene);
  scene->scene.seconds = 2;  // the head turns as over the 5 s scene's first 2 s
  const tracking::MarkerLayout layout = tracking::load_layout(tracking::default_layout_path());
  const auto from_frame_32 = [](const PhotoRow& row) {
    return evaluate_tracks(std::span(row.suite.truth).subspan(32),
                           std::span(row.suite.tracks).subspan(32));
  };
  const PhotoRow row = run_photo_scenario(*scene, default_faces_dir(), layout, {}, {});
  EXPECT_EQ(last_noted(row, "identified again"), 32);
  ASSERT_EQ(row.suite.tracks.size(), 50u);
  EXPECT_EQ(from_frame_32(row).astray_observations, 0);
  EXPECT_EQ(from_frame_32(row).swap_observations, 0);
  // With two looks only, the lip corner keeps the name.
  tracking::TrackerOptions two_looks;
  two_looks.second_look_tries = 2;
  EXPECT_GT(from_frame_32(run_photo_scenario(*scene, default_faces_dir(), layout, {}, two_looks))
                .astray_observations,
            10);
}

// The held-out late start of seed 5 (2008_002079.jpg entering from the right, the first 2 s),
// its dots looked for at their points: the take starts on frame 23 as the face slows, with the
// right mid-brow's name on the upper lid's dot, 27 px below its own. The second look, frame 33,
// names every dot right with a margin of 0.97 against the start's 1.00; a naming that much less
// sure is as sure (kMarginNoise), and the take starts again on it. The frames from the start
// to it take its names (tracking/name_corrections.hpp).
TEST(PhotoSuite, ASecondNamingAsSureWithinItsNoiseStartsTheTakeAgain) {
  if (!std::filesystem::is_directory(default_faces_dir()))
    GTEST_SKIP() << default_faces_dir() << " is absent (../shared beside the repository)";
  std::optional<PhotoScenario> scene = default_scenario("enter_s5", "photo_scenes_heldout.json");
  ASSERT_TRUE(scene);
  scene->scene.seconds = 2;
  const PhotoRow row = run_photo_scenario(*scene, default_faces_dir(),
                                          tracking::load_layout(tracking::default_layout_path()),
                                          {}, looked_for_at_points());
  EXPECT_EQ(last_noted(row, "identified again"), 33);  // 10 frames after the start
  ASSERT_EQ(row.suite.tracks.size(), 50u);
  const TrackEvalResult after = evaluate_tracks(std::span(row.suite.truth).subspan(33),
                                                std::span(row.suite.tracks).subspan(33));
  EXPECT_EQ(after.swap_observations, 0);
  EXPECT_EQ(after.astray_observations, 0);
  // Before it, the start (frame 23) had the mid-brow's name on the lid's dot: frame 33 says so,
  // and the frames before are written under the right names, back to frame 20 (20-22 followed
  // back from the start, tracking/start_backfill.hpp).
  bool mid_brow_renamed = false;
  for (const tracking::NameCorrection& c : row.suite.tracks[33].corrections)
    mid_brow_renamed |= c.from.starts_with("brow_r_mid");
  EXPECT_TRUE(mid_brow_renamed);
  EXPECT_EQ(row.suite.tracks[33].corrected_since, 20);
  EXPECT_EQ(evaluate_tracks(std::span(row.suite.truth).subspan(20, 13),
                            std::span(row.suite.tracks).subspan(20, 13))
                .swap_observations,
            0);
}

// Re-acquisition taking any blob that passes the dot checks, its look not asked
// (TrackerOptions::found_look_allowance).
tracking::TrackerOptions finding_any_blob(tracking::TrackerOptions o = {}) {
  o.found_look_allowance = -1;
  return o;
}

// In the held-out small face at 640x480 (small_vga_s5 in data/eval/photo_scenes_heldout.json),
// identification weighing a faint blob half as much as by default (ink_weight 0.15), the dots
// looked for at their points, names the right inner eye-corner dot on the eye's own corner, 11 px
// off. The second look, 10 frames on, places the name back on its dot, which is round and stands
// on plain skin where the corner is elongated; without it the name stays on the corner.
TEST(PhotoSuite, AnEyeDotNamedOnTheEyesCornerIsPlacedBackByItsLook) {
  if (!std::filesystem::is_directory(default_faces_dir()))
    GTEST_SKIP() << default_faces_dir() << " is absent (../shared beside the repository)";
  const std::optional<PhotoScenario> scene =
      default_scenario("small_vga_s5", "photo_scenes_heldout.json");
  ASSERT_TRUE(scene);
  const tracking::MarkerLayout layout = tracking::load_layout(tracking::default_layout_path());
  const auto after_it = [](const PhotoRow& row) {
    return evaluate_tracks(std::span(row.suite.truth).subspan(11),
                           std::span(row.suite.tracks).subspan(11));
  };
  tracking::TrackerOptions faint_weighed_less = looked_for_at_points();
  faint_weighed_less.identification.ink_weight = 0.15;
  const PhotoRow row =
      run_photo_scenario(*scene, default_faces_dir(), layout, {}, faint_weighed_less);
  EXPECT_EQ(last_noted(row, "second look:"), 10);
  EXPECT_EQ(after_it(row).astray_observations, 0);
  tracking::TrackerOptions without = faint_weighed_less;
  without.second_look_after = 0;
  const PhotoRow without_it = run_photo_scenario(*scene, default_faces_dir(), layout, {}, without);
  EXPECT_GT(after_it(without_it).astray_observations, 50);
}

// The held-out hand scene of seed 8 (2008_001009.jpg, talking): on frame 10 the second look
// names the left upper-lip dot, followed on its dot, on the lip's edge 17 px off. The followed
// dot, beside the dark lip, cannot be measured afresh there, and the blob on the edge passes
// the dot checks but looks far less like a dot than the followed one has (Dot::surround +
// elongation - 1: 0.77 against its usual 0.33). A followed name is moved by the second look only
// onto a blob that looks like its dot, as a lost dot is found again
// (TrackerOptions::found_look_allowance); moved onto any blob that passes, it sat on the lip's
// edge for two frames, 17 px from its dot.
TEST(PhotoSuite, TheSecondLookMovesNoFollowedNameOntoABlobUnlikeItsDot) {
  if (!std::filesystem::is_directory(default_faces_dir()))
    GTEST_SKIP() << default_faces_dir() << " is absent (../shared beside the repository)";
  const std::optional<PhotoScenario> scene =
      default_scenario("hand_s8", "photo_scenes_heldout.json");
  ASSERT_TRUE(scene);
  const PhotoRow row = run_photo_scenario(*scene, default_faces_dir(),
                                          tracking::load_layout(tracking::default_layout_path()));
  for (long k : {10, 11}) {
    const auto tracked = at(row.suite.tracks[k], "lip_top_l");
    const auto truth = at(row.suite.truth[k], "lip_top_l");
    ASSERT_TRUE(truth.valid);
    ASSERT_TRUE(tracked.valid) << "frame " << k;
    EXPECT_LT(cv::norm(tracked.position - truth.position), 0.5) << "frame " << k;
  }
}

// The held-out hand scene of seed 7 (2008_001009.jpg, talking), its dots looked for at their
// points: the left mouth-corner dot, by the moustache, is not seen when tracking starts, and the
// identification's guess at its start place lies 28 px from it; the second look names it. Looked
// for after the hand passes where its neighbours put that guess, it was never found again; a
// mouth-corner dot, it is now carried while lost from where it was last seen, and every dot is
// back within 3 frames of the hand.
TEST(PhotoSuite, ADotNamedAfterTheStartIsFoundAgainAfterTheHand) {
  if (!std::filesystem::is_directory(default_faces_dir()))
    GTEST_SKIP() << default_faces_dir() << " is absent (../shared beside the repository)";
  const std::optional<PhotoScenario> scene =
      default_scenario("hand_s7", "photo_scenes_heldout.json");
  ASSERT_TRUE(scene);
  const tracking::MarkerLayout layout = tracking::load_layout(tracking::default_layout_path());
  const PhotoRow row =
      run_photo_scenario(*scene, default_faces_dir(), layout, {}, looked_for_at_points());
  EXPECT_GE(row.occlusions, 1);
  EXPECT_GE(row.worst_reacquire, 0);  // -1: one never came back
  EXPECT_LE(row.worst_reacquire, 3);
}

// The first blurred scene (2008_001322.jpg, seed 1): a lost dot is found again only on a blob
// that looks about as much like a dot as it has while followed. Where any blob that passes the
// dot checks is taken, the right outer eye-corner dot, lost at frame 26, is found on the eye's
// own corner 14 px off and followed there to the end: 99 observations astray (a name on
// something that is no dot).
TEST(PhotoSuite, ALostDotIsNotFoundOnAFeatureThatLooksLessLikeADot) {
  if (!std::filesystem::is_directory(default_faces_dir()))
    GTEST_SKIP() << default_faces_dir() << " is absent (../shared beside the repository)";
  const std::optional<PhotoScenario> scene = default_scenario("blur");
  ASSERT_TRUE(scene);
  const tracking::MarkerLayout layout = tracking::load_layout(tracking::default_layout_path());
  const PhotoRow row = run_photo_scenario(*scene, default_faces_dir(), layout);
  EXPECT_EQ(row.suite.result.swap_observations, 0);
  EXPECT_LE(row.suite.result.error_px.p95, 0.6);  // the blurred frames' aim
  const PhotoRow any =
      run_photo_scenario(*scene, default_faces_dir(), layout, {}, finding_any_blob());
  EXPECT_GT(any.suite.result.astray_observations, 50);
}

// The big-dot 640x480 scene (2008_001009.jpg, dots 14 px) starts with the right mid-brow dot
// unnamed; the one dot between its place and the upper lid's is the lid's. Re-acquisition
// took it for the mid-brow whenever it lay nearer the mid-brow's place, a toss LK followed to
// the end; it leaves a dot about as near another lost marker's place alone, as identification
// does (IdentificationOptions::unnamed_rival).
TEST(PhotoSuite, ADotAboutAsNearAnotherLostMarkersPlaceIsNotTakenBack) {
  const std::optional<PhotoRow> row = default_row("bigdots_vga");
  if (!row) GTEST_SKIP() << without_shared();
  EXPECT_EQ(row->suite.result.swap_observations, 0);
}

TEST(PhotoSuite, UnknownKeyIsAnInputErrorNamingIt) {
  const auto path = std::filesystem::temp_directory_path() / "rostro_photo_scenes_test.json";
  std::ofstream(path) << R"({"scenarios": [{"name": "a", "photo": "x.jpg", "blurr": 3}]})";
  try {
    load_photo_scenes(path);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("blurr"), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace rostro::eval
