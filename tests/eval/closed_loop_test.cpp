// The closed loop of issue 6: its definition file, head sweeps in the drive, and short clips
// run end to end (render -> track -> TakeMapper -> score).

#include "eval/closed_loop.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>

#include "eval/track_metrics.hpp"
#include "facecore/data_path.hpp"
#include "facecore/error.hpp"
#include "facecore/head_generator.hpp"
#include "render/render_error.hpp"

namespace rostro::eval {
namespace {

constexpr int kOpenJaw = 3, kHeadPitch = 48, kHeadYaw = 49;

std::filesystem::path temp_file(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / ("rostro_loop_test_" + name);
  std::ofstream(path) << text;
  return path;
}

// The message of the InputError `f` throws, or "" when it throws none.
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ClosedLoopFile, DefaultFileHasTheIssuesScenarios) {
  const LoopDefinition d = load_closed_loop(default_closed_loop_path());
  const LoopScenario* still = nullptr;
  const LoopScenario* turns = nullptr;
  for (const auto& s : d.scenarios) {
    if (s.name == "still") still = &s;
    if (s.name == "turns") turns = &s;
  }
  ASSERT_NE(still, nullptr);
  ASSERT_NE(turns, nullptr);
  EXPECT_TRUE(still->fap.empty());  // the range of motion
  EXPECT_EQ(still->head.yaw_deg, 0);
  EXPECT_DOUBLE_EQ(still->aim, 0.05);
  EXPECT_EQ(turns->head.yaw_deg, 25);
  EXPECT_EQ(turns->head.pitch_deg, 15);
  EXPECT_DOUBLE_EQ(turns->aim, 0.08);
  EXPECT_EQ(turns->neutral_lead, 1);  // the file's default
  EXPECT_EQ(turns->synth.width, 640);
}

TEST(ClosedLoopFile, ErrorsNameTheFileAndTheKey) {
  const auto unknown = temp_file("unknown.json", R"({"scenarios": [{"name": "a", "yawn": 3}]})");
  const std::string e1 = error_of([&] { load_closed_loop(unknown); });
  EXPECT_NE(e1.find(unknown.string()), std::string::npos) << e1;
  EXPECT_NE(e1.find("scenario 1"), std::string::npos) << e1;
  EXPECT_NE(e1.find("'yawn'"), std::string::npos) << e1;

  const auto type = temp_file(
      "type.json", R"({"scenarios": [{"name": "a"}, {"name": "b", "head_yaw": "lots"}]})");
  const std::string e2 = error_of([&] { load_closed_loop(type); });
  EXPECT_NE(e2.find(type.string()), std::string::npos) << e2;
  EXPECT_NE(e2.find("scenario 2 (b)"), std::string::npos) << e2;
  EXPECT_NE(e2.find("'head_yaw'"), std::string::npos) << e2;

  const auto drive =
      temp_file("drive.json", R"({"scenarios": [{"name": "a", "drive": "no/such.fap"}]})");
  const std::string e3 = error_of([&] { load_closed_loop(drive); });
  EXPECT_NE(e3.find(drive.string()), std::string::npos) << e3;
  EXPECT_NE(e3.find("'drive'"), std::string::npos) << e3;

  const auto empty = temp_file("empty.json", R"({"scenarios": []})");
  const std::string e4 = error_of([&] { load_closed_loop(empty); });
  EXPECT_NE(e4.find(empty.string()), std::string::npos) << e4;
  EXPECT_NE(e4.find("'scenarios'"), std::string::npos) << e4;

  const auto repeat = temp_file("repeat.json", R"({"scenarios": [{"name": "a"}, {"name": "a"}]})");
  EXPECT_NE(error_of([&] { load_closed_loop(repeat); }).find("repeats"), std::string::npos);
  const auto aim = temp_file("aim.json", R"({"scenarios": [{"name": "a", "aim": 5}]})");
  EXPECT_NE(error_of([&] { load_closed_loop(aim); }).find("'aim'"), std::string::npos);
  const auto bare_aim =
      temp_file("bare_aim.json", R"({"scenarios": [{"name": "a", "markerless_aim": 0}]})");
  EXPECT_NE(error_of([&] { load_closed_loop(bare_aim); }).find("'markerless_aim'"),
            std::string::npos);
}

TEST(ClosedLoopFile, AimsDependOnTheHeadsMotionAndOnMarkers) {
  const auto path = temp_file("aims.json", R"({"scenarios": [{"name": "still"},
      {"name": "turns", "head_yaw": 25}, {"name": "own", "aim": 0.2, "markerless_aim": 0.3}]})");
  const LoopDefinition d = load_closed_loop(path);
  ASSERT_EQ(d.scenarios.size(), 3u);
  // Markers: issue 6's 5 % and 8 %; a bare face: issue 17's 10 % and 15 %.
  EXPECT_DOUBLE_EQ(d.scenarios[0].aim, 0.05);
  EXPECT_DOUBLE_EQ(d.scenarios[0].markerless_aim, 0.10);
  EXPECT_DOUBLE_EQ(d.scenarios[1].aim, 0.08);
  EXPECT_DOUBLE_EQ(d.scenarios[1].markerless_aim, 0.15);
  EXPECT_DOUBLE_EQ(d.scenarios[2].aim, 0.2);
  EXPECT_DOUBLE_EQ(d.scenarios[2].markerless_aim, 0.3);
}

TEST(ClosedLoopFile, AbsentSharedDriveIsSkippedNotAnError) {
  const auto dir = std::filesystem::temp_directory_path() / "rostro_loop_test_shared";
  std::filesystem::create_directories(dir);
  ::setenv("ROSTRO_SHARED", dir.c_str(), 1);
  const auto path = temp_file(
      "shared.json", R"({"scenarios": [{"name": "x", "drive": "shared:fixtures/none.fap"}]})");
  const LoopDefinition d = load_closed_loop(path);
  ::unsetenv("ROSTRO_SHARED");
  ASSERT_EQ(d.scenarios.size(), 1u);
  EXPECT_NE(d.scenarios[0].skip_reason.find((dir / "fixtures/none.fap").string()),
            std::string::npos)
      << d.scenarios[0].skip_reason;
}

// A scenario may render the head generated at another density; below the generator's least
// count the file is refused, naming the scenario and the key.
TEST(ClosedLoopFile, HeadVerticesNameAGeneratedHead) {
  const auto file = temp_file(
      "heads.json",
      R"({"head_vertices": 20000, "scenarios": [{"name": "a"}, {"name": "b", "head_vertices": 0}]})");
  const LoopDefinition d = load_closed_loop(file);
  ASSERT_EQ(d.scenarios.size(), 2u);
  EXPECT_EQ(d.scenarios[0].head_vertices, 20000);  // the file's default
  EXPECT_EQ(d.scenarios[1].head_vertices, 0);      // the head given
  const auto few =
      temp_file("few.json", R"({"scenarios": [{"name": "a", "head_vertices": 1000}]})");
  const std::string e = error_of([&] { load_closed_loop(few); });
  EXPECT_NE(e.find("scenario 1 (a)"), std::string::npos) << e;
  EXPECT_NE(e.find("'head_vertices'"), std::string::npos) << e;
  // The heads file names heads of other densities, or the default head seen from elsewhere.
  const LoopDefinition heads = load_closed_loop(data_file("eval/closed_loop_heads.json"));
  for (const LoopScenario& s : heads.scenarios)
    EXPECT_TRUE(s.head_vertices > 0 || s.synth.elevation_deg != 0) << s.name;
}

// A scenario may hold the camera above or below the face and take its own image size; out of
// range, the file is refused, naming the scenario and the key.
TEST(ClosedLoopFile, CameraElevationAndSizePerScenario) {
  const auto file = temp_file("views.json", R"({"size": [640, 480], "scenarios": [{"name": "a"},
      {"name": "b", "camera_elevation": -6, "size": [1280, 720]}]})");
  const LoopDefinition d = load_closed_loop(file);
  ASSERT_EQ(d.scenarios.size(), 2u);
  EXPECT_EQ(d.scenarios[0].synth.elevation_deg, 0);
  EXPECT_EQ(d.scenarios[0].synth.width, 640);  // the file's size
  EXPECT_EQ(d.scenarios[1].synth.elevation_deg, -6);
  EXPECT_EQ(d.scenarios[1].synth.width, 1280);
  EXPECT_EQ(d.scenarios[1].synth.height, 720);
  const auto steep =
      temp_file("steep.json", R"({"scenarios": [{"name": "a", "camera_elevation": 75}]})");
  std::string e = error_of([&] { load_closed_loop(steep); });
  EXPECT_NE(e.find("scenario 1 (a)"), std::string::npos) << e;
  EXPECT_NE(e.find("'camera_elevation'"), std::string::npos) << e;
  const auto small = temp_file("small.json", R"({"scenarios": [{"name": "a", "size": [8, 8]}]})");
  e = error_of([&] { load_closed_loop(small); });
  EXPECT_NE(e.find("scenario 1 (a)"), std::string::npos) << e;
  EXPECT_NE(e.find("'size'"), std::string::npos) << e;
}

TEST(HeadSweeps, WrittenIntoFaps48To50AfterTheLeadIn) {
  LoopScenario s;
  s.seconds = 3;
  s.neutral_lead = 1;
  s.head.yaw_deg = 25;
  s.head.pitch_deg = 15;
  s.head.period_s = 4;
  const FapStream d = loop_drive(s);
  ASSERT_EQ(d.frames.size(), 100u);  // 1 s lead + 3 s at 25 fps
  for (int i = 0; i < 25; ++i) EXPECT_FALSE(d.frames[i].has(kHeadYaw)) << i;  // still lead
  EXPECT_EQ(d.frames[25].get(kHeadYaw), 0);
  EXPECT_TRUE(d.frames[25].has(kHeadYaw));
  // A quarter period after the lead: +25 degrees toward the face's left, in AU (1e-5 rad).
  EXPECT_NEAR(d.frames[50].get(kHeadYaw), 25 * M_PI / 180 / 1e-5, 1);
  double pitch_max = 0;
  for (const FapFrame& f : d.frames) pitch_max = std::max(pitch_max, std::abs(f.get(kHeadPitch)));
  EXPECT_NEAR(pitch_max, degrees_to_au(15), degrees_to_au(0.5));
  // The range of motion is still there beside the head.
  EXPECT_GT(d.frames[37].get(kOpenJaw), 300);
}

// Short clips rendered, tracked and mapped; skipped without OpenGL or the default head.
class ClosedLoopRun : public ::testing::Test {
 protected:
  void SetUp() override {
    try {
      model_.emplace(load_default_face_model());
      library_.emplace(ExpressionLibrary::load_default());
      layout_.emplace(tracking::load_layout(tracking::default_layout_path()));
    } catch (const InputError& e) {
      GTEST_SKIP() << "no default head or layout: " << e.what();
    }
  }
  LoopResult run(const LoopScenario& s) {
    return run_loop_scenario(s, *model_, &*library_, *layout_);
  }
  std::optional<FaceModel> model_;
  std::optional<ExpressionLibrary> library_;
  std::optional<tracking::MarkerLayout> layout_;
};

// The issue's aim for a still head, on the FAP the range of motion drives hardest: open_jaw
// within 5 % of its range, on the exact tracks (the fit alone) and on the tracked markers.
TEST_F(ClosedLoopRun, StillHeadOpenJawWithinFivePercent) {
  LoopScenario s;
  s.name = s.title = "still, 2 s";
  s.seconds = 2;  // the jaw opens, then the lip corners rise
  LoopResult r;
  try {
    r = run(s);
  } catch (const render::RenderUnavailable& e) {
    GTEST_SKIP() << "no OpenGL: " << e.what();
  }
  EXPECT_EQ(r.frames, 75);
  ASSERT_NE(std::find(r.tracked.begin(), r.tracked.end(), kOpenJaw), r.tracked.end());
  for (LoopMethod m : {LoopMethod::CeresOnTruth, LoopMethod::Ceres}) {
    const LoopScore& score = r.score(m);
    EXPECT_EQ(score.calibration_frames, 25) << method_label(m);
    const FapError* jaw = score.find(kOpenJaw);
    ASSERT_NE(jaw, nullptr) << method_label(m);
    ASSERT_TRUE(jaw->rms_share_of_range.has_value());
    EXPECT_LT(*jaw->rms_share_of_range, 0.05)
        << method_label(m) << ": open_jaw RMS " << jaw->rms << " MNS units";
  }
  // The table names every tracked FAP.
  const std::string table = loop_fap_table_text(r);
  EXPECT_NE(table.find("open_jaw"), std::string::npos);
}

// One method's failure is that method's row: a layout without a nose-tip dot leaves the seed
// method no reference point to calibrate on, and the Ceres fits, which need none, are still
// scored beside it.
TEST_F(ClosedLoopRun, AMethodThatCannotCalibrateFailsInItsOwnRow) {
  tracking::MarkerLayout no_nose_tip = *layout_;
  std::erase_if(no_nose_tip.markers, [](const tracking::MarkerSpec& m) {
    return m.feature_point == FeaturePointId{9, 3};
  });
  ASSERT_EQ(no_nose_tip.markers.size() + 1, layout_->markers.size());
  LoopScenario s;
  s.name = s.title = "still, 2 s";
  s.seconds = 2;
  LoopResult r;
  try {
    r = run_loop_scenario(s, *model_, &*library_, no_nose_tip);
  } catch (const render::RenderUnavailable& e) {
    GTEST_SKIP() << "no OpenGL: " << e.what();
  }
  ASSERT_FALSE(r.tracked.empty());
  const LoopScore& seed = r.score(LoopMethod::Seed2d);
  EXPECT_NE(seed.failure.find("nose-tip"), std::string::npos) << seed.failure;
  EXPECT_FALSE(seed.met);
  EXPECT_EQ(seed.scored, 0);
  EXPECT_EQ(seed.not_output, r.tracked);
  EXPECT_NE(loop_summary_text({r}).find("failed: "), std::string::npos);
  for (LoopMethod m : {LoopMethod::Ceres, LoopMethod::CeresOnTruth}) {
    const LoopScore& ceres = r.score(m);
    EXPECT_TRUE(ceres.failure.empty()) << method_label(m) << ": " << ceres.failure;
    EXPECT_EQ(ceres.scored, static_cast<int>(r.tracked.size())) << method_label(m);
  }
}

// The same head generated with four times the vertices (facecore/head_generator.hpp): a face the
// tracker was not tuned on, its eyes' corners and brows sampled elsewhere, and so read a little
// differently by dlib's landmarks, which place the dots for their naming. Looked for at their
// feature points, the inner brow dots are named on the brows' inner ends and followed there
// (153 observations astray); looked for beside them, where the layout says they are worn, every
// name is right.
TEST_F(ClosedLoopRun, AHeadOfAnotherDensityIsTrackedAsWell) {
  const FaceModel dense = generate_head(HeadOptions{20000});
  // The default file's still head (640x480, the range of motion).
  const LoopDefinition d = load_closed_loop(default_closed_loop_path());
  const auto still = std::find_if(d.scenarios.begin(), d.scenarios.end(),
                                  [](const LoopScenario& s) { return s.name == "still"; });
  ASSERT_NE(still, d.scenarios.end());
  const LoopScenario& s = *still;
  // Observations named on something that is not their dot: swapped or astray.
  std::optional<LoopResult> beside_run;
  auto misnamed = [&](const tracking::TrackerOptions& options) {
    const LoopResult r = run_loop_scenario(s, dense, &*library_, *layout_, {}, options);
    if (options.identification.dots_beside_points) beside_run = r;
    const TrackEvalResult e = evaluate_tracks(r.truth_tracks, r.tracks);
    std::printf("%s: %ld swapped, %ld astray, %ld lost\n",
                options.identification.dots_beside_points ? "beside" : "at points",
                e.swap_observations, e.astray_observations, e.lost_observations);
    return e.swap_observations + e.astray_observations;
  };
  long beside = 0, at_points = 0;
  tracking::TrackerOptions points;
  points.identification.dots_beside_points = false;
  try {
    beside = misnamed({});
    at_points = misnamed(points);
  } catch (const render::RenderUnavailable& e) {
    GTEST_SKIP() << "no OpenGL: " << e.what();
  }
  EXPECT_EQ(beside, 0);
  EXPECT_GT(at_points, 100);
  // The fit models the head it is shown (its own deformation, not the default head's, whose
  // mid-brow and lids move otherwise at another sampling: 54 % on raise_l_m_eyebrow).
  ASSERT_TRUE(beside_run.has_value());
  const LoopScore& exact = beside_run->score(LoopMethod::CeresOnTruth);
  EXPECT_TRUE(exact.met) << "worst share " << exact.max_share << " on FAP " << exact.worst_fap;
}

// The exact tracks with Gaussian noise (`rostro eval loop --truth-noise`): a fourth score,
// labelled with its sigma, whose error grows with the noise (about in proportion: the fit is
// linear in small errors).
TEST_F(ClosedLoopRun, NoisyExactTracksScoreWorseWithMoreNoise) {
  LoopScenario s;
  s.name = s.title = "still, 2 s";
  s.seconds = 2;
  std::vector<double> mean_share;
  for (double sigma : {0.5, 2.0}) {
    s.truth_noise_px = sigma;
    LoopResult r;
    try {
      r = run(s);
    } catch (const render::RenderUnavailable& e) {
      GTEST_SKIP() << "no OpenGL: " << e.what();
    }
    ASSERT_EQ(r.scores.size(), 4u);
    const LoopScore& noisy = r.score(LoopMethod::CeresOnNoisyTruth);
    EXPECT_EQ(noisy.label(), sigma == 0.5 ? "ceres, exact tracks + 0.5 px noise"
                                          : "ceres, exact tracks + 2 px noise");
    EXPECT_EQ(noisy.scored, r.score(LoopMethod::CeresOnTruth).scored);
    EXPECT_GT(noisy.mean_share, 2 * r.score(LoopMethod::CeresOnTruth).mean_share) << sigma;
    mean_share.push_back(noisy.mean_share);
  }
  EXPECT_GT(mean_share[1], 2 * mean_share[0]);  // four times the noise
}

// A head turned +25 degrees in FAP 49 (toward the face's left) reads back with the same sign.
TEST_F(ClosedLoopRun, HeadYawInFap49ReadsBackWithItsSign) {
  LoopScenario s;
  s.name = s.title = "yaw, 2 s";
  s.seconds = 2;
  s.head.yaw_deg = 25;
  LoopResult r;
  try {
    r = run(s);
  } catch (const render::RenderUnavailable& e) {
    GTEST_SKIP() << "no OpenGL: " << e.what();
  }
  const FapStream drive = loop_drive(s);
  const long peak = 50;  // a quarter period after the 1 s lead: +25 degrees
  ASSERT_NEAR(drive.frames[peak].get(kHeadYaw), degrees_to_au(25), 1);
  for (LoopMethod m : {LoopMethod::CeresOnTruth, LoopMethod::Ceres}) {
    const LoopScore& score = r.score(m);
    const FapFrame* at_peak = nullptr;
    for (const FapFrame& f : score.estimate.frames)
      if (f.index == peak) at_peak = &f;
    ASSERT_NE(at_peak, nullptr) << method_label(m);
    ASSERT_TRUE(at_peak->has(kHeadYaw)) << method_label(m);
    EXPECT_GT(at_peak->get(kHeadYaw), degrees_to_au(12.5))
        << method_label(m) << ": FAP 49 read " << at_peak->get(kHeadYaw) << " AU for "
        << degrees_to_au(25);
    const FapError* yaw = score.find(kHeadYaw);
    ASSERT_NE(yaw, nullptr);
    ASSERT_TRUE(yaw->correlation.has_value());
    EXPECT_GT(*yaw->correlation, 0.9) << method_label(m);
  }
}

// The closed loop's head turns at 640x480 (data/eval/closed_loop.json, cut after frame 95): as
// the head turns back, the left inner eye-corner dot is seen edge-on beside the eye slit's
// dark corner. For one frame (84) its blob took in the corner and was centred 2.35 px into the
// eye while LK followed the dot itself to 0.2 px, and the dot was then followed there, 2-2.5 px
// off, to the end of the cut (a tighter snap limit for the eye dots was made for it; with the
// eye dots painted beside the contour the case no longer arises, and the limit was removed).
// Every frame it is reported in must be near its true place.
TEST_F(ClosedLoopRun, EdgeOnEyeCornerIsNotFollowedIntoTheSlit) {
  LoopScenario turns;
  for (const LoopScenario& s : load_closed_loop(default_closed_loop_path()).scenarios)
    if (s.name == "turns") turns = s;
  ASSERT_EQ(turns.name, "turns");
  turns.seconds = 2.84;  // 1 s lead + 71 frames: frames 0-95
  LoopResult r;
  try {
    r = run(turns);
  } catch (const render::RenderUnavailable& e) {
    GTEST_SKIP() << "no OpenGL: " << e.what();
  }
  ASSERT_EQ(r.tracks.size(), r.truth_tracks.size());
  ASSERT_GT(r.tracks.size(), 90u);
  int seen = 0;
  for (size_t k = 0; k < r.tracks.size(); ++k) {
    const auto find = [](const tracking::TrackedFrame& f) -> const tracking::MarkerObservation* {
      for (const auto& o : f.markers)
        if (o.marker == "eye_l_in") return &o;
      return nullptr;
    };
    const tracking::MarkerObservation* seen_at = find(r.tracks[k]);
    const tracking::MarkerObservation* truth = find(r.truth_tracks[k]);
    ASSERT_NE(seen_at, nullptr);
    ASSERT_NE(truth, nullptr);
    if (!seen_at->valid || !truth->valid) continue;
    ++seen;
    EXPECT_LT(cv::norm(seen_at->position - truth->position), 1.0) << "frame " << k;
  }
  EXPECT_GT(seen, 70) << "the corner dot should be followed most of the clip";
}

}  // namespace
}  // namespace rostro::eval
