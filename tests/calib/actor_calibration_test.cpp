// FAPU estimation and actor calibration from synthetic neutral frames.
#include "calib/actor_calibration.hpp"

#include <gtest/gtest.h>

#include "calib/actor_prior.hpp"
#include "calib/fapu_estimation.hpp"
#include "calib/generic_face.hpp"
#include "facecore/data_path.hpp"
#include "facecore/error.hpp"
#include "tests/support/synthetic_face.hpp"
#include "tracking/ibug_mapping.hpp"

namespace rostro::calib {
namespace {

TEST(GenericFace, HasAll84PointsAndIsSymmetric) {
  const auto& face = generic_face_points();
  EXPECT_EQ(face.size(), static_cast<std::size_t>(kFeaturePointCount));
  for (const auto& [id, p] : face) {
    const auto& twin = face.at(mirror(id));
    EXPECT_DOUBLE_EQ(twin.x(), -p.x()) << id.str();
    EXPECT_DOUBLE_EQ(twin.y(), p.y()) << id.str();
  }
  const Fapu f = fapu_from_feature_points(face);
  EXPECT_DOUBLE_EQ(f.es0, 63);
  EXPECT_DOUBLE_EQ(f.ens0, 45);
  EXPECT_DOUBLE_EQ(f.mns0, 21);
  EXPECT_DOUBLE_EQ(f.mw0, 50);
  EXPECT_DOUBLE_EQ(f.irisd0, 10);
}

FeaturePointPositions only(const FeaturePointPositions& face, std::vector<FeaturePointId> ids) {
  FeaturePointPositions out;
  for (auto id : ids) out[id] = face.at(id);
  return out;
}

TEST(FapuEstimation, EstimatesUnmarkedPointsFromTheirNeighbours) {
  // A face 1.2 times the prior: the estimates must scale with it.
  FeaturePointPositions big;
  for (const auto& [id, p] : generic_face_points()) big[id] = 1.2 * p + Eigen::Vector3d(5, -7, 0);
  const auto marked = only(
      big,
      {{3, 7}, {3, 11}, {3, 8}, {3, 12}, {9, 1}, {9, 2}, {8, 1}, {8, 3}, {8, 4}, {4, 1}, {4, 2}});
  const FapuEstimate e = estimate_fapu(marked, generic_face_points());
  const Fapu truth = fapu_from_feature_points(big);
  EXPECT_NEAR(e.fapu.es0, truth.es0, 1e-9);
  EXPECT_NEAR(e.fapu.ens0, truth.ens0, 1e-9);
  EXPECT_NEAR(e.fapu.mns0, truth.mns0, 1e-9);
  EXPECT_NEAR(e.fapu.mw0, truth.mw0, 1e-9);
  EXPECT_NEAR(e.fapu.irisd0, truth.irisd0, 1e-9);  // the prior's IRISD0/ES0 ratio
  EXPECT_NEAR(e.scale_to_prior, 1.2, 1e-9);
  for (const char* key : {"3.5", "3.6", "9.15", "2.2", "IRISD0"})
    EXPECT_TRUE(e.notes.count(key)) << key;
  EXPECT_NE(e.notes.at("9.15").find("nose wings"), std::string::npos);
  EXPECT_NE(e.notes.at("IRISD0").find("ES0"), std::string::npos);
  EXPECT_FALSE(e.notes.count("8.3")) << "8.3 carries a marker";
}

TEST(FapuEstimation, LidMarkersGiveIrisdDirectly) {
  auto face = generic_face_points();
  face[{3, 3}].y() -= 2;  // a wider-open eye than the prior's
  const auto marked = only(face, {{3, 1}, {3, 3}, {3, 5}, {3, 6}, {9, 15}, {2, 2}, {8, 3}, {8, 4}});
  const FapuEstimate e = estimate_fapu(marked, generic_face_points());
  EXPECT_NEAR(e.fapu.irisd0, 12, 1e-9);
  EXPECT_TRUE(e.notes.empty()) << "every FAPU point is marked";
  EXPECT_THROW(estimate_fapu(only(face, {{3, 1}}), generic_face_points()), InputError);
}

TEST(FapuEstimation, LidDotsBesideTheMarginsDoNotMeasureIrisd) {
  // Dots are painted on the lid skin clear of the lashes, here 2.3 mm above and below the
  // margins: their distance is not the iris's.
  const FeaturePointPositions prior = generic_face_points();
  auto face = prior;
  for (FeaturePointId lid : {FeaturePointId{3, 1}, FeaturePointId{3, 2}}) face[lid].y() += 2.3;
  for (FeaturePointId lid : {FeaturePointId{3, 3}, FeaturePointId{3, 4}}) face[lid].y() -= 2.3;
  const auto marked =
      only(face, {{3, 1}, {3, 2}, {3, 3}, {3, 4}, {3, 5}, {3, 6}, {9, 15}, {2, 2}, {8, 3}, {8, 4}});
  const double truth = fapu_from_feature_points(prior).irisd0;
  EXPECT_NEAR(estimate_fapu(marked, prior).fapu.irisd0, truth + 4.6, 1e-9);  // lids on margins
  const FapuEstimate beside = estimate_fapu(marked, prior, false);
  EXPECT_NEAR(beside.fapu.irisd0, truth, 1e-9);  // ES0 x the prior's IRISD0/ES0
  EXPECT_NE(beside.notes.at("IRISD0").find("beside"), std::string::npos);
}

TEST(ActorPrior, OnlyLandmarksOnTheLidsMeasureIrisd) {
  const ActorPrior prior = load_actor_prior();
  const auto dots = tracking::load_layout(data_file("layouts/default.json"));
  EXPECT_FALSE(actor_calibration_options(dots, prior, "a").lid_markers_on_margin);
  const auto landmarks = tracking::landmark_layout(tracking::default_ibug_mapping(), prior.points);
  EXPECT_TRUE(actor_calibration_options(landmarks, prior, "a").lid_markers_on_margin);
}

TEST(ActorCalibration, DotsBesideTheirPointsTakeThePriorsPlaceAndMotion) {
  const ActorPrior prior = load_actor_prior();
  if (!prior.head) GTEST_SKIP() << "the default head did not load: no prior head to test";
  auto layout = tracking::load_layout(data_file("layouts/default.json"));
  // The inner eye corners painted on their points, the outer ones beside: the pupils, the
  // corners' midpoints, move out unless each dot's offset is taken off.
  for (auto& m : layout.markers)
    if (m.id == "eye_l_in" || m.id == "eye_r_in") m.beside_mm.reset();
  const ActorCalibrationOptions o = actor_calibration_options(layout, prior, "a");
  // The layout paints the upper lid dot a few mm above the lid's midpoint: on the prior's skin
  // there, moved by the upper lid's FAP nearly as much as the midpoint, but less: the skin's
  // own motion, not the point's.
  ASSERT_TRUE(o.beside.count("lid_l_up"));
  const PriorPlace& lid = o.beside.at("lid_l_up");
  const Eigen::Vector3d point = prior.points.at({3, 1});
  EXPECT_NEAR(lid.position.x(), point.x(), 1e-3);
  const cv::Point2d beside = *layout.find("lid_l_up")->beside_mm;
  EXPECT_NEAR(lid.position.y(), point.y() + beside.y, 1e-3);
  ASSERT_TRUE(lid.motion.count(19));
  const double share = lid.motion.at(19).y() / prior.motion.at({3, 1}).at(19).y();
  EXPECT_GT(share, 0.8);
  EXPECT_LT(share, 0.99);

  // A neutral view of the prior head wearing the layout: each dot at its own place.
  CameraIntrinsics camera;
  camera.image_size = {1280, 720};
  camera.fx = camera.fy = 1000, camera.cx = 639.5, camera.cy = 359.5;
  tracking::TrackedFrame frame;
  for (const auto& m : layout.markers) {
    Eigen::Vector3d x;
    if (o.beside.count(m.id))
      x = o.beside.at(m.id).position;
    else if (!m.is_tag() && prior.points.count(m.feature_point))
      x = prior.points.at(m.feature_point);
    else if (o.marker_priors.count(m.id))
      x = o.marker_priors.at(m.id);
    else
      continue;
    tracking::MarkerObservation obs;
    obs.marker = m.id, obs.feature_point = m.feature_point, obs.valid = true;
    const double depth = 600 - x.z();  // the head faces the camera 600 mm away
    obs.position = {camera.cx + camera.fx * x.x() / depth, camera.cy - camera.fy * x.y() / depth};
    frame.markers.push_back(obs);
  }
  const ActorProfile p = calibrate_actor({frame, frame}, camera, o);
  EXPECT_EQ(p.marker_motion.at("lid_l_up"), lid.motion);
  // The FAPU are measured at the points: the prior head's own.
  const Fapu& truth = prior.head->fapu;
  EXPECT_NEAR(p.fapu.es0, truth.es0, 0.01 * truth.es0);
  EXPECT_NEAR(p.fapu.ens0, truth.ens0, 0.01 * truth.ens0);
  EXPECT_NEAR(p.fapu.mns0, truth.mns0, 0.01 * truth.mns0);
  EXPECT_NEAR(p.fapu.mw0, truth.mw0, 0.01 * truth.mw0);
  EXPECT_NEAR(p.fapu.irisd0, truth.irisd0, 0.01 * truth.irisd0);
  // And the dot where it was painted, above the point, at the actor's scale.
  const auto* dot = p.find_marker("lid_l_up");
  ASSERT_TRUE(dot && dot->position);
  EXPECT_NEAR(dot->position->y() - p.find_marker("eye_l_in")->position->y(),
              lid.position.y() - prior.points.at({3, 11}).y(), 0.2);
}

TEST(ActorCalibration, NeutralFramesGiveFapuShapeAndPose) {
  const auto actor = test::make_actor(1.04, 0.97, 1.0);
  const auto pose = test::head_pose(0, 0, 0, {10, -20, 600});
  std::mt19937 rng(21);
  std::vector<tracking::TrackedFrame> frames;
  for (int i = 0; i < 20; ++i) {
    auto f = test::render(actor, {}, pose, 0.3, rng, i);
    if (i % 4 == 0) f.markers[5].valid = false;  // lost now and then: still used
    if (i > 3) f.markers[6].valid = false;       // lost most of the time: left out
    frames.push_back(std::move(f));
  }
  const ActorProfile p = calibrate_actor(frames, actor.camera, test::calibration_options());
  EXPECT_EQ(p.neutral_frames, 20);
  EXPECT_EQ(p.markers.size(), actor.markers.size() - 1);
  EXPECT_FALSE(p.find_marker(actor.markers[6].first));
  EXPECT_TRUE(p.fapu_notes.count("left out: " + actor.markers[6].first));
  EXPECT_EQ(p.find_marker(actor.markers[5].first)->frames_seen, 15);
  EXPECT_TRUE(p.find_marker("tag36h11:0")->rigid);

  // FAPU (mm) within 2 % of the actor's true ones; pupils and nose base were estimated.
  EXPECT_NEAR(p.fapu.es0, actor.fapu.es0, 0.02 * actor.fapu.es0);
  EXPECT_NEAR(p.fapu.ens0, actor.fapu.ens0, 0.02 * actor.fapu.ens0);
  EXPECT_NEAR(p.fapu.mns0, actor.fapu.mns0, 0.03 * actor.fapu.mns0);
  EXPECT_NEAR(p.fapu.mw0, actor.fapu.mw0, 0.02 * actor.fapu.mw0);
  EXPECT_NEAR(p.fapu.irisd0, actor.fapu.irisd0, 0.05 * actor.fapu.irisd0);
  EXPECT_TRUE(p.fapu_notes.count("3.5"));
  EXPECT_TRUE(p.fapu_notes.count("9.15"));
  EXPECT_TRUE(p.fapu_notes.count("2.2"));
  // Image FAPU: the same ratios in pixels (about 1000/600 px per mm).
  EXPECT_NEAR(p.fapu_image.mw0 / p.fapu_image.es0, actor.fapu.mw0 / actor.fapu.es0, 0.02);

  // The 3D shape matches the actor up to the overall scale the single view cannot know.
  const auto* lip = p.find_marker("mouth_l");
  const auto* brow = p.find_marker("brow_r_out");
  ASSERT_TRUE(lip && lip->position && brow && brow->position);
  const Eigen::Vector3d measured = *lip->position - *brow->position;
  const Eigen::Vector3d truth = actor.shape.at({8, 3}) - actor.shape.at({4, 6});
  EXPECT_LT((measured - truth).norm(), 0.03 * truth.norm());
  ASSERT_TRUE(p.neutral_pose);
  EXPECT_NEAR(p.neutral_pose->translation[2], 600, 20);
  EXPECT_NEAR(p.neutral_pose->rotation[0], M_PI, 0.03);
}

TEST(ActorCalibration, RefusesTooLittleData) {
  const auto actor = test::make_actor();
  EXPECT_THROW(calibrate_actor({}, actor.camera), InputError);
  std::mt19937 rng(1);
  auto frame = test::render(actor, {}, test::head_pose(0, 0, 0), 0, rng);
  for (std::size_t i = 3; i < frame.markers.size(); ++i) frame.markers[i].valid = false;
  EXPECT_THROW(calibrate_actor({frame}, actor.camera), InputError);
}

TEST(ActorCalibration, PlacesLayoutMarkersOnThePrior) {
  const auto& prior = generic_face_points();
  // A layout in its own frame: origin at the nose tip, 10 % larger than the prior.
  std::vector<NominalMarker> layout;
  const Eigen::Vector3d nose = prior.at({9, 3});
  for (FeaturePointId id : {FeaturePointId{4, 1}, {8, 3}, {2, 1}, {9, 3}})
    layout.push_back({"m" + id.str(), id, 1.1 * (prior.at(id) - nose)});
  layout.push_back({"tag", std::nullopt, 1.1 * (Eigen::Vector3d(0, 53, 10) - nose)});
  const auto placed = place_nominal_markers(layout, prior);
  EXPECT_TRUE(placed.at("tag").isApprox(Eigen::Vector3d(0, 53, 10), 1e-9));
  EXPECT_TRUE(placed.at("m8.3").isApprox(prior.at({8, 3}), 1e-9));
  EXPECT_THROW(place_nominal_markers({layout.back()}, prior), InputError);
}

TEST(ActorCalibration, RecalibratingAtAnotherFocalLengthMatchesCalibratingThere) {
  const auto actor = test::make_actor();  // f = 1000 px
  std::mt19937 rng(31);
  std::vector<tracking::TrackedFrame> frames;
  for (int i = 0; i < 10; ++i)
    frames.push_back(test::render(actor, {}, test::head_pose(0, 0, 0), 0.0, rng, i));
  CameraIntrinsics guess = actor.camera;
  guess.fx = guess.fy = 650;
  guess.source = "default: a guess";
  const ActorProfile first = calibrate_actor(frames, guess, test::calibration_options());
  const ActorProfile direct = calibrate_actor(frames, actor.camera, test::calibration_options());
  const ActorProfile redone = recalibrate_focal(first, 1000.0);
  EXPECT_EQ(redone.camera.fx, 1000.0);
  EXPECT_EQ(redone.camera.source, guess.source);  // still a default: the fit keeps refining
  ASSERT_TRUE(redone.neutral_pose && direct.neutral_pose);
  EXPECT_NEAR(redone.neutral_pose->translation[2], direct.neutral_pose->translation[2], 5.0);
  EXPECT_NEAR(first.neutral_pose->translation[2] / redone.neutral_pose->translation[2], 0.65, 0.03);
  double worst = 0;
  for (const NeutralMarker& m : redone.markers) {
    const NeutralMarker* d = direct.find_marker(m.marker);
    ASSERT_TRUE(d && d->position && m.position) << m.marker;
    worst = std::max(worst, (*m.position - *d->position).norm());
  }
  EXPECT_LT(worst, 1.0) << "mm between the redone shape and one calibrated at 1000 px";
  EXPECT_EQ(redone.fapu.mns0, first.fapu.mns0);  // the FAPU are kept
  EXPECT_EQ(redone.markers.size(), first.markers.size());
}

TEST(ActorPrior, HeadbandTagsSitOnThePriorHeadsSkin) {
  // The layout's nominal place of the middle tag floats 12 mm in front of the default head's
  // forehead; a tag lies on the skin, and its depth decides the head pose once the head turns.
  const ActorPrior prior = load_actor_prior();
  if (prior.skin.empty()) GTEST_SKIP() << "the default head did not load: no skin to test";
  const auto layout = tracking::load_layout(data_file("layouts/default.json"));
  const ActorCalibrationOptions o = actor_calibration_options(layout, prior, "a");
  int tags = 0;
  for (const auto& m : layout.markers) {
    if (!m.is_tag()) continue;
    ++tags;
    const Eigen::Vector3d& x = o.marker_priors.at(m.id);
    double nearest = 1e9;
    for (const Eigen::Vector3d& v : prior.skin) nearest = std::min(nearest, (v - x).norm());
    EXPECT_LT(nearest, 1e-9) << m.id << " is not on the skin";
    EXPECT_GT(x.y(), prior.points.at({4, 3}).y()) << m.id << " should be above the brows";
  }
  EXPECT_EQ(tags, 3);
}

}  // namespace
}  // namespace rostro::calib
