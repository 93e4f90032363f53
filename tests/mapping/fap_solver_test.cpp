// The Ceres fit recovers known FAP values and head poses from synthetic projections.
#include "mapping/fap_solver.hpp"

#include <gtest/gtest.h>

#include "calib/actor_calibration.hpp"
#include "facecore/error.hpp"
#include "mapping/fap_mapper.hpp"
#include "tests/support/model_projection.hpp"
#include "tests/support/synthetic_face.hpp"

namespace rostro::mapping {
namespace {

using test::head_pose;
using test::make_actor;
using test::render;

// Checks every FAP of `truth` against `fit`; tolerance = rel x |value| + the FAP's motion of
// `mm` millimetres on the synthetic actor (so noise counts alike for FAPs of every unit).
// Returns the RMS error as a displacement in mm over all of them.
double expect_faps(const std::map<int, double>& truth, const FapFrame& fit, double rel, double mm,
                   const std::string& what) {
  const Fapu fapu = test::make_actor().fapu;
  double sq = 0;
  for (const auto& [id, value] : truth) {
    EXPECT_TRUE(fit.has(id)) << what << ": FAP " << id << " not fitted";
    const double unit = fapu.unit_size(fap_info(id).unit);
    const double tolerance = rel * std::abs(value) + mm / unit;
    EXPECT_NEAR(fit.get(id), value, tolerance)
        << what << ": FAP " << id << " " << fap_info(id).name;
    sq += std::pow((fit.get(id) - value) * unit, 2);
  }
  return std::sqrt(sq / static_cast<double>(truth.size()));
}

std::vector<tracking::TrackedFrame> neutral_frames(const test::SyntheticActor& a,
                                                   const tracking::HeadPose& pose, double noise,
                                                   std::mt19937& rng) {
  std::vector<tracking::TrackedFrame> frames;
  for (int i = 0; i < 15; ++i) frames.push_back(render(a, {}, pose, noise, rng, i));
  return frames;
}

TEST(FapSolver, BadOptionIsNamedInOneLine) {
  EXPECT_NO_THROW(SolverOptions{}.validate());
  const auto actor = make_actor();
  const auto neutral = head_pose(0, 0, 0);
  SolverOptions o;
  o.max_iterations = 0;
  try {
    FapSolver solver(test::exact_profile(actor, neutral), o);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "SolverOptions::max_iterations = 0: should be > 0");
  }
  o = {};
  o.prior_weight_of[3] = -1;
  try {
    o.validate();
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "SolverOptions::prior_weight_of[3] = -1: should be >= 0");
  }
}

TEST(FapSolver, OptionsSetByName) {
  SolverOptions o;
  set_solver_option(o, "pose_prior_weight=0");
  set_solver_option(o, "max_iterations=40");
  set_solver_option(o, "model.fit_depth_faps=true");
  EXPECT_EQ(o.pose_prior_weight, 0);
  EXPECT_EQ(o.max_iterations, 40);
  EXPECT_TRUE(o.model.fit_depth_faps);
  EXPECT_THROW(set_solver_option(o, "prior_weight_of=1"), InputError);
  EXPECT_THROW(set_solver_option(o, "max_iterations=many"), InputError);
}

TEST(FapSolver, ExactProfileStillHeadNoiseFree) {
  const auto actor = make_actor();
  const auto neutral = head_pose(0, 0, 0);
  FapSolver solver(test::exact_profile(actor, neutral));
  std::mt19937 rng(3);
  const auto truth = test::test_expression();
  const FitResult r = solver.fit(render(actor, truth, neutral, 0, rng));
  ASSERT_TRUE(r.ok);
  EXPECT_LT(r.rms_px, 0.05);
  // The only bias is the weak pull toward neutral on a first frame (about 0.25 %).
  EXPECT_LT(expect_faps(truth, r.faps, 0.04, 0.01, "exact still"), 0.03);
  EXPECT_NEAR(r.faps.get(49), 0.0, 200.0);  // head yaw, AU (200 AU = 0.11 degree)
}

TEST(FapSolver, CalibratedProfileStillHeadWithNoise) {
  const auto actor = make_actor();
  const auto neutral = head_pose(0, 0, 0);
  std::mt19937 rng(5);
  const auto profile = calib::calibrate_actor(neutral_frames(actor, neutral, 0.3, rng),
                                              actor.camera, test::calibration_options());
  FapSolver solver(profile);
  for (double scale : {1.0, -0.5, 0.3}) {
    const auto truth = test::test_expression(scale);
    const FitResult r = solver.fit(render(actor, truth, neutral, 0.3, rng));
    ASSERT_TRUE(r.ok);
    EXPECT_LT(r.rms_px, 1.0);
    // 0.3 px of noise is 0.18 mm on the face at 600 mm: each FAP within 5 % plus 4 sigma of
    // that, and the RMS over all FAPs within 0.3 mm.
    const std::string what = "calibrated still, scale " + std::to_string(scale);
    EXPECT_LT(expect_faps(truth, r.faps, 0.05, 0.7, what), 0.3) << what;
  }
}

TEST(FapSolver, RecoversPoseAndFapsUnderYawAndPitch) {
  const auto actor = make_actor();
  const auto neutral = head_pose(0, 0, 0);
  std::mt19937 rng(7);
  const auto profile = calib::calibrate_actor(neutral_frames(actor, neutral, 0.3, rng),
                                              actor.camera, test::calibration_options());
  FapSolver solver(profile);
  const auto truth = test::test_expression(0.8);
  for (double yaw : {-25.0, 0.0, 25.0})
    for (double pitch : {-15.0, 15.0}) {
      solver.reset();  // cold start from the neutral pose: the hardest case
      const auto pose = head_pose(yaw, pitch, 3.0, {-30, 15, 650});
      const FitResult r = solver.fit(render(actor, truth, pose, 0.3, rng));
      const std::string what = "yaw " + std::to_string(yaw) + " pitch " + std::to_string(pitch);
      ASSERT_TRUE(r.ok) << what;
      EXPECT_NEAR(r.faps.get(49) * kAngleUnitRad, test::deg(yaw), test::deg(1.5)) << what;
      EXPECT_NEAR(r.faps.get(48) * kAngleUnitRad, test::deg(pitch), test::deg(1.5)) << what;
      EXPECT_NEAR(r.faps.get(50) * kAngleUnitRad, test::deg(3.0), test::deg(1.5)) << what;
      EXPECT_NEAR(r.pose.translation[2], 650.0, 30.0) << what;
      // Looser: the 3D shape's depths come from the prior, so turned heads cost accuracy.
      EXPECT_LT(expect_faps(truth, r.faps, 0.10, 1.0, what), 0.35) << what;
    }
}

TEST(FapSolver, WarmStartedSequenceTracksAMovingHead) {
  const auto actor = make_actor();
  const auto neutral = head_pose(0, 0, 0);
  std::mt19937 rng(11);
  FapSolver solver(test::exact_profile(actor, neutral));
  for (int i = 0; i < 50; ++i) {
    const double t = i / 49.0;
    const auto truth = test::test_expression(std::sin(t * M_PI));
    const auto& clamped = truth;
    const auto pose = head_pose(25 * std::sin(2 * M_PI * t), 15 * std::sin(4 * M_PI * t), 0);
    const FitResult r = solver.fit(render(actor, clamped, pose, 0.2, rng, i));
    ASSERT_TRUE(r.ok) << "frame " << i;
    EXPECT_LT(r.rms_px, 0.6) << "frame " << i;
    // 0.2 px of noise is 0.12 mm on the face: RMS over all FAPs within twice that.
    EXPECT_LT(expect_faps(clamped, r.faps, 0.05, 0.5, "frame " + std::to_string(i)), 0.25);
  }
}

// A head swept to yaw +-25 and pitch +-15 degrees, warm-started frame to frame, on exact
// projections with a profile calibrated from noise-free neutral frames: the head FAPs and the
// expression come back tightly (the remaining error is the calibration's: prior depths).
TEST(FapSolver, TurnedHeadOnExactProjectionsRecoversHeadAndExpressionTightly) {
  const auto actor = make_actor();
  const auto neutral = head_pose(0, 0, 0);
  std::mt19937 rng(19);
  const auto profile = calib::calibrate_actor(neutral_frames(actor, neutral, 0.0, rng),
                                              actor.camera, test::calibration_options());
  FapSolver solver(profile);
  double worst_yaw = 0, worst_pitch = 0;
  for (int i = 0; i < 60; ++i) {
    const double t = i / 59.0;
    const double yaw = 25 * std::sin(2 * M_PI * t), pitch = 15 * std::sin(4 * M_PI * t);
    const auto truth = test::test_expression(0.5 + 0.5 * std::cos(3 * M_PI * t));
    const FitResult r = solver.fit(render(actor, truth, head_pose(yaw, pitch, 0), 0, rng, i));
    const std::string what = "frame " + std::to_string(i);
    ASSERT_TRUE(r.ok) << what;
    worst_yaw = std::max(worst_yaw, std::abs(r.faps.get(49) * kAngleUnitRad - test::deg(yaw)));
    worst_pitch =
        std::max(worst_pitch, std::abs(r.faps.get(48) * kAngleUnitRad - test::deg(pitch)));
    EXPECT_LT(expect_faps(truth, r.faps, 0.03, 0.1, what), 0.06) << what;
  }
  EXPECT_LT(worst_yaw, test::deg(0.3));
  EXPECT_LT(worst_pitch, test::deg(0.3));
}

// A unidirectional FAP the markers push below 0 (here the jaw pushed up into the skull) rests
// exactly on 0, and the fit does not crawl there: Ceres' projected bounds took 20-25
// iterations on such frames, the active set takes a few per round.
TEST(FapSolver, UnidirectionalFapsRestOnZeroInFewIterations) {
  const auto actor = make_actor();
  const auto neutral = head_pose(0, 0, 0);
  FapSolver solver(test::exact_profile(actor, neutral));
  std::mt19937 rng(23);
  auto truth = test::test_expression(0.5);
  truth[3] = -60;  // open_jaw is unidirectional
  const FitResult r = solver.fit(render(actor, truth, head_pose(10, -5, 0), 0, rng));
  ASSERT_TRUE(r.ok);
  ASSERT_TRUE(r.faps.has(3));
  EXPECT_EQ(r.faps.get(3), 0.0);
  EXPECT_LE(r.iterations, 15);
  for (const auto& [id, value] : truth) {
    if (fap_info(id).bidirectional) continue;
    EXPECT_GE(r.faps.get(id), 0.0) << fap_info(id).name;
  }
}

// Without a calibrated camera the focal length is a guess; head turns tell the fit the real
// one, and the FAPs come out better for it.
TEST(FapSolver, DefaultFocalLengthIsRefinedFromHeadTurns) {
  const auto actor = make_actor();  // f = 1000 px
  const auto neutral = head_pose(0, 0, 0);
  calib::CameraIntrinsics guess = calib::default_intrinsics(actor.camera.image_size);
  guess.fx = guess.fy = 650;  // 35 % short
  std::mt19937 rng(29);
  const auto profile = calib::calibrate_actor(neutral_frames(actor, neutral, 0.0, rng), guess,
                                              test::calibration_options());
  SolverOptions fixed;
  fixed.refine_default_focal = false;
  FapSolver refined(profile), kept(profile, fixed);
  double sq_refined = 0, sq_kept = 0;
  double focal = 0;
  for (int i = 0; i < 120; ++i) {
    const double t = i / 60.0;
    const auto truth = test::test_expression(0.5 + 0.5 * std::cos(3 * M_PI * t));
    const auto frame =
        render(actor, truth, head_pose(25 * std::sin(2 * M_PI * t), 15 * std::sin(4 * M_PI * t), 0),
               0, rng, i);
    const FitResult a = refined.fit(frame), b = kept.fit(frame);
    ASSERT_TRUE(a.ok && b.ok) << "frame " << i;
    focal = a.focal_px;
    EXPECT_EQ(b.focal_px, 650.0);
    if (i < 60) continue;  // the second sweep: after one sweep of head turns
    for (const auto& [id, value] : truth) {
      const double unit = actor.fapu.unit_size(fap_info(id).unit);
      sq_refined += std::pow((a.faps.get(id) - value) * unit, 2);
      sq_kept += std::pow((b.faps.get(id) - value) * unit, 2);
    }
  }
  EXPECT_NEAR(focal, 1000.0, 150.0);
  EXPECT_LT(sq_refined, 0.5 * sq_kept);
}

// The mapper also recalibrates the actor at the refined focal length (the solver alone adjusts
// the shape to first order and stops short): after head turns the focal length is the
// camera's and the FAPs are as good as with the true intrinsics.
TEST(FapMapper, DefaultFocalLengthConvergesWithRecalibration) {
  const auto actor = make_actor();  // f = 1000 px
  std::mt19937 rng(37);
  calib::CameraIntrinsics guess = calib::default_intrinsics(actor.camera.image_size);
  guess.fx = guess.fy = 650;
  const auto neutral = neutral_frames(actor, head_pose(0, 0, 0), 0.0, rng);
  MapperOptions refine, keep;
  keep.solver.refine_default_focal = false;
  const auto profile = calib::calibrate_actor(neutral, guess, test::calibration_options());
  const auto exact = calib::calibrate_actor(neutral, actor.camera, test::calibration_options());
  auto refined = make_fap_mapper(profile, refine);
  auto kept = make_fap_mapper(profile, keep);
  auto known = make_fap_mapper(exact, keep);
  double sq_refined = 0, sq_kept = 0, sq_known = 0;
  for (int i = 0; i < 240; ++i) {
    const double t = i / 60.0;
    const auto truth = test::test_expression(0.5 + 0.5 * std::cos(3 * M_PI * t));
    const auto frame =
        render(actor, truth, head_pose(25 * std::sin(2 * M_PI * t), 15 * std::sin(4 * M_PI * t), 0),
               0, rng, i);
    const FapFrame a = refined->map(frame), b = kept->map(frame), c = known->map(frame);
    if (i < 180) continue;  // the last of four sweeps
    for (const auto& [id, value] : truth) {
      const double unit = actor.fapu.unit_size(fap_info(id).unit);
      sq_refined += std::pow((a.get(id) - value) * unit, 2);
      sq_kept += std::pow((b.get(id) - value) * unit, 2);
      sq_known += std::pow((c.get(id) - value) * unit, 2);
    }
  }
  EXPECT_LT(sq_refined, 0.1 * sq_kept);
  EXPECT_LT(std::sqrt(sq_refined), 2.0 * std::sqrt(sq_known) + 1e-3);
}

TEST(FapSolver, InvalidMarkersAreIgnored) {
  const auto actor = make_actor();
  const auto neutral = head_pose(0, 0, 0);
  FapSolver solver(test::exact_profile(actor, neutral));
  std::mt19937 rng(13);
  auto truth = test::test_expression();
  auto frame = render(actor, truth, neutral, 0, rng);
  for (auto& m : frame.markers)
    if (m.marker == "brow_l_mid" || m.marker == "lip_bot_l") {
      m.valid = false;
      m.position = {-5000, 1e6};  // garbage that must not matter
    }
  frame.markers.push_back({"not_in_profile", {5, 1}, {100, 100}, true, 1});  // unknown: ignored
  const FitResult r = solver.fit(frame);
  ASSERT_TRUE(r.ok);
  EXPECT_EQ(r.markers_used, 32);
  EXPECT_FALSE(r.faps.has(33)) << "raise_l_m_eyebrow has no valid marker";
  EXPECT_FALSE(r.faps.has(57)) << "raise_b_lip_lm_o has no valid marker";
  truth.erase(33);
  truth.erase(57);
  EXPECT_LT(expect_faps(truth, r.faps, 0.04, 0.01, "with invalid markers"), 0.03);
}

TEST(FapSolver, TooFewMarkersGiveNoFit) {
  const auto actor = make_actor();
  const auto neutral = head_pose(0, 0, 0);
  FapSolver solver(test::exact_profile(actor, neutral));
  std::mt19937 rng(17);
  auto frame = render(actor, {}, neutral, 0, rng);
  for (std::size_t i = 3; i < frame.markers.size(); ++i) frame.markers[i].valid = false;
  const FitResult r = solver.fit(frame);
  EXPECT_FALSE(r.ok);
  EXPECT_TRUE(r.faps.mask.none());
}

TEST(FapSolver, UnidirectionalFapsStayNonNegative) {
  const auto actor = make_actor();
  const auto neutral = head_pose(0, 0, 0);
  FapSolver solver(test::exact_profile(actor, neutral));
  std::mt19937 rng(19);
  // The chin pushed up past neutral: open_jaw cannot go below 0.
  const FitResult r = solver.fit(render(actor, {{3, -200}}, neutral, 0, rng));
  ASSERT_TRUE(r.ok);
  EXPECT_GE(r.faps.get(3), 0.0);
  EXPECT_LT(r.faps.get(3), 1.0);
}

// The cheeks are unidirectional in MPEG-4, yet the Xface streams draw them down (-8 ENS in
// anger, fear, disgust) and the head renders that; clamped at 0, the cheek dots' miss went
// into the head pitch. The fit lets them go below 0 (SolverOptions::signed_faps), while the
// jaw still rests on 0.
TEST(FapSolver, CheeksMayBeDrawnDownWhileTheJawStaysBounded) {
  const auto actor = make_actor();
  const auto neutral = head_pose(0, 0, 0);
  std::mt19937 rng(29);
  auto truth = test::test_expression(0.5);
  truth[41] = -20;
  truth[42] = -15;
  double signed_pitch_error = 0, clamped_pitch_error = 0;
  {
    FapSolver solver(test::exact_profile(actor, neutral));
    const FitResult r = solver.fit(render(actor, truth, head_pose(8, 5, 0), 0, rng));
    ASSERT_TRUE(r.ok);
    EXPECT_NEAR(r.faps.get(41), -20, 1.0);
    EXPECT_NEAR(r.faps.get(42), -15, 1.0);
    signed_pitch_error = std::abs(r.faps.get(48) * kAngleUnitRad - test::deg(5));
  }
  {
    SolverOptions clamped;
    clamped.signed_faps.clear();
    FapSolver solver(test::exact_profile(actor, neutral), clamped);
    const FitResult r = solver.fit(render(actor, truth, head_pose(8, 5, 0), 0, rng));
    ASSERT_TRUE(r.ok);
    EXPECT_EQ(r.faps.get(41), 0.0) << "without signed_faps the cheek rests on its bound";
    clamped_pitch_error = std::abs(r.faps.get(48) * kAngleUnitRad - test::deg(5));
  }
  // The clamped cheek's miss is taken up by the head pitch.
  EXPECT_LT(signed_pitch_error, 0.5 * clamped_pitch_error);
}

// A profile whose jaw carries the chin boss and the lower lip (as the default head's motion
// does), seen with the chin dot hidden: the chin boss and the lip then move with open_jaw and
// with their own FAPs alike. Holding depress_chin (SolverOptions::hold_while_hidden) lets the
// chin boss read the jaw; without the hold the jaw opening leaks into the chin and lip FAPs.
TEST(FapSolver, HiddenChinHoldsDepressChinSoTheJawIsRead) {
  const auto actor = make_actor();
  const auto neutral = head_pose(0, 0, 0);
  calib::ActorProfile profile = test::exact_profile(actor, neutral);
  profile.marker_motion["chin"] = {{3, {0, -1, 0}}, {15, {1, 0, 0}}};
  profile.marker_motion["chin_boss"] = {{3, {0, -0.8, 0}}, {18, {0, 1, 0}}};
  profile.marker_motion["lip_bot"] = {{3, {0, -0.6, 0}}, {52, {0, 1, 0}}};
  profile.marker_motion["lip_bot_l"] = {{3, {0, -0.55, 0}}, {57, {0, 1, 0}}};
  profile.marker_motion["lip_bot_r"] = {{3, {0, -0.55, 0}}, {58, {0, 1, 0}}};
  const MarkerModel model = build_marker_model(profile);
  // Frames rendered from the profile's own model: the fit's only unknown is what it holds.
  auto frame_of = [&](const std::map<int, double>& faps, const tracking::HeadPose& pose,
                      long index) {
    tracking::TrackedFrame f;
    f.frame = index;
    for (const ModelMarker& m : model.markers)
      f.markers.push_back({m.marker, m.feature_point,
                           test::project_model_marker(m, faps, pose, actor.camera),
                           m.marker != "chin", 1.0});
    return f;
  };
  auto worst_jaw_error = [&](const SolverOptions& options) {
    FapSolver solver(profile, options);
    double worst = 0;
    for (int i = 0; i < 30; ++i) {
      const double t = i / 29.0;
      // The jaw opens and closes while the lip is raised against it; the chin boss rests.
      const std::map<int, double> truth = {{3, 300 * std::sin(M_PI * t)},
                                           {52, -150 * std::sin(2 * M_PI * t)},
                                           {57, -120 * std::sin(2 * M_PI * t)},
                                           {58, -120 * std::sin(2 * M_PI * t)}};
      const FitResult r = solver.fit(frame_of(truth, head_pose(20, 12, 0), i));
      EXPECT_TRUE(r.ok);
      worst = std::max(worst, std::abs(r.faps.get(3) - truth.at(3)));
      if (!options.hold_while_hidden.empty()) {
        EXPECT_NEAR(r.faps.get(18), 0.0, 1.0) << "frame " << i;
        EXPECT_NEAR(r.faps.get(52), truth.at(52), 3.0) << "frame " << i;
      }
    }
    return worst;
  };
  EXPECT_LT(worst_jaw_error(SolverOptions{}), 3.0);  // MNS, of a 300 MNS opening
  SolverOptions no_hold;
  no_hold.hold_while_hidden.clear();
  EXPECT_GT(worst_jaw_error(no_hold), 20.0) << "the test no longer shows the ambiguity";
}

TEST(FapSolver, GainsAndRangesFromTheProfileAreApplied) {
  const auto actor = make_actor();
  const auto neutral = head_pose(0, 0, 0);
  auto profile = test::exact_profile(actor, neutral);
  profile.fap_gains[31] = {2.0, std::nullopt, std::nullopt};
  profile.fap_gains[53] = {1.0, std::nullopt, 100.0};
  FapSolver solver(profile);
  std::mt19937 rng(23);
  const FitResult r = solver.fit(render(actor, {{31, 50}, {53, 140}}, neutral, 0, rng));
  ASSERT_TRUE(r.ok);
  EXPECT_NEAR(r.faps.get(31), 100.0, 1.0);
  EXPECT_NEAR(r.faps.get(53), 100.0, 1e-9);
}

// A still head under a fast-talking mouth, as the Xface streams drive it: the lower lip swings
// by hundreds of MNS from one frame to the next and the jaw sometimes closes a few units past
// neutral (open_jaw -7). A frontal face says little about a tenth of a degree of pitch (it
// moves the markers by hundredths of a pixel), so whatever the face FAPs fail to explain goes
// there: the pull toward the previous frame's FAPs (a lag) and a jaw held at its bound both
// did (60-180 AU on the Xface drivers' exact tracks). The head must stay still.
TEST(FapSolver, FastMouthOnAStillHeadLeavesThePoseStill) {
  const auto actor = make_actor();
  const auto neutral = head_pose(0, 0, 0);
  std::mt19937 rng(31);
  FapSolver solver(test::exact_profile(actor, neutral));
  double worst_pitch = 0, worst_yaw = 0, worst_roll = 0, worst_jaw = 0;
  for (int i = 0; i < 60; ++i) {
    const double t = static_cast<double>(i);
    std::map<int, double> faps;
    for (int id : {52, 57, 58}) faps[id] = 300 * std::sin(2.1 * t);  // raise_b_*lip_o
    for (int id : {51, 55, 56}) faps[id] = 100 * std::sin(1.3 * t);  // lower_t_*lip_o
    faps[3] = std::max(-7.0, 250 * std::sin(0.9 * t));               // open_jaw
    faps[59] = faps[60] = 80 * std::sin(0.7 * t);                    // raise_*_cornerlip_o
    const FitResult r = solver.fit(render(actor, faps, neutral, 0, rng, i));
    ASSERT_TRUE(r.ok) << "frame " << i;
    worst_pitch = std::max(worst_pitch, std::abs(r.faps.get(48)));
    worst_yaw = std::max(worst_yaw, std::abs(r.faps.get(49)));
    worst_roll = std::max(worst_roll, std::abs(r.faps.get(50)));
    // The fit follows the jaw below 0; the reported value stops at the FAP's bound.
    worst_jaw = std::max(worst_jaw, std::abs(r.faps.get(3) - std::max(0.0, faps[3])));
  }
  // 10 AU is 0.006 degree.
  EXPECT_LT(worst_pitch, 10.0) << "head_pitch (AU) moved with the mouth";
  EXPECT_LT(worst_yaw, 10.0);
  EXPECT_LT(worst_roll, 10.0);
  EXPECT_LT(worst_jaw, 2.0) << "open_jaw (MNS)";
}

// RMS of the head FAPs' error (AU) over a warm-started take: pitch, yaw.
std::array<double, 2> head_error_rms(const SolverOptions& options, double yaw_amplitude,
                                     double noise_px) {
  const auto actor = make_actor();
  const auto neutral = head_pose(0, 0, 0);
  std::mt19937 rng(37);
  FapSolver solver(test::exact_profile(actor, neutral), options);
  double pitch_sq = 0, yaw_sq = 0;
  const int frames = 100;
  for (int i = 0; i < frames; ++i) {
    const double t = static_cast<double>(i) / 25.0;  // 25 fps, a 4 s head period
    const double yaw = yaw_amplitude * std::sin(2 * M_PI * t / 4.0);
    const auto truth = test::test_expression(0.5 + 0.5 * std::sin(2.3 * t));
    const FitResult r = solver.fit(render(actor, truth, head_pose(yaw, 0, 0), noise_px, rng, i));
    EXPECT_TRUE(r.ok) << "frame " << i;
    pitch_sq += std::pow(r.faps.get(48), 2);
    yaw_sq += std::pow(r.faps.get(49) - test::deg(yaw) / kAngleUnitRad, 2);
  }
  return {std::sqrt(pitch_sq / frames), std::sqrt(yaw_sq / frames)};
}

// The pose prior (SolverOptions::pose_prior_weight) steadies the poorly seen head pitch of a
// still head under tracking noise, and its prediction keeps up with a head turning at the
// closed loop's pace (yaw +-25 degrees over 4 s).
TEST(FapSolver, PosePriorSteadiesThePitchWithoutLaggingATurn) {
  SolverOptions off;
  off.pose_prior_weight = 0;
  const auto still_off = head_error_rms(off, 0, 0.1);
  const auto still_on = head_error_rms({}, 0, 0.1);
  EXPECT_LT(still_on[0], 0.8 * still_off[0])
      << "head_pitch RMS (AU) with the prior " << still_on[0] << ", without " << still_off[0];
  const auto turning_off = head_error_rms(off, 25, 0);
  const auto turning_on = head_error_rms({}, 25, 0);
  // 100 AU is 0.06 degree; the turn itself spans 87,000 AU.
  EXPECT_LT(turning_on[1], turning_off[1] + 100.0)
      << "head_yaw RMS (AU) with the prior " << turning_on[1] << ", without " << turning_off[1];
}

TEST(HeadRotationFaps, SignsFollowTheFapTable) {
  const auto neutral = head_pose(0, 0, 0);
  const auto yaw = head_rotation_faps(neutral, head_pose(10, 0, 0));
  EXPECT_NEAR(yaw[1] * kAngleUnitRad, test::deg(10), 1e-9);
  EXPECT_NEAR(yaw[0], 0, 1e-6);
  const auto pitch = head_rotation_faps(neutral, head_pose(0, -7, 0));
  EXPECT_NEAR(pitch[0] * kAngleUnitRad, test::deg(-7), 1e-9);
  const auto roll = head_rotation_faps(neutral, head_pose(0, 0, 4));
  EXPECT_NEAR(roll[2] * kAngleUnitRad, test::deg(4), 1e-9);
}

}  // namespace
}  // namespace rostro::mapping
