// Actor profile JSON: a round trip keeps every field; malformed files are named clearly.
#include "calib/actor_profile.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "facecore/error.hpp"

namespace rostro::calib {
namespace {

ActorProfile sample() {
  ActorProfile p;
  p.name = "ana";
  p.fapu = {63.1, 45.2, 21.3, 50.4, 10.5};
  p.fapu_image = {120.5, 88.25, 40.125, 96.0, 20.0};
  p.fapu_notes = {{"3.5", "midpoint of the left eye corners"}, {"IRISD0", "ES0 x 0.16"}};
  p.camera.image_size = {1280, 720};
  p.camera.fx = 1001.5;
  p.camera.fy = 999.25;
  p.camera.cx = 641;
  p.camera.cy = 359.5;
  p.camera.distortion = {0.1, -0.02, 0, 0, 0.001};
  p.camera.reprojection_error = 0.31;
  p.camera.source = "chessboard 9x6, 12 views";
  p.neutral_pose = tracking::HeadPose{{3.1, 0.01, -0.02}, {5, -10, 610}};
  p.shape_source = "generic";
  p.neutral_frames = 25;
  NeutralMarker a{"brow_l_in", {4, 1}, {700.25, 300.5}, Eigen::Vector3d(15, 17, 3), 25, false};
  NeutralMarker b{"tag36h11:0", {}, {640, 200}, std::nullopt, 20, true};
  p.markers = {a, b};
  p.fap_gains[3] = {1.2, 0.0, 1000.0};
  p.fap_gains[31] = {0.8, std::nullopt, std::nullopt};
  return p;
}

std::string error_of(const std::string& text) {
  try {
    actor_profile_from_json(text, "ana.json");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(ActorProfile, FileRoundTripKeepsEverything) {
  const auto path = std::filesystem::path(ROSTRO_BINARY_DIR) / "test_actor_profile.json";
  const ActorProfile p = sample();
  write_actor_profile(path, p);
  const ActorProfile q = read_actor_profile(path);
  EXPECT_EQ(q.name, p.name);
  EXPECT_DOUBLE_EQ(q.fapu.es0, p.fapu.es0);
  EXPECT_DOUBLE_EQ(q.fapu.irisd0, p.fapu.irisd0);
  EXPECT_DOUBLE_EQ(q.fapu_image.mns0, p.fapu_image.mns0);
  EXPECT_EQ(q.fapu_notes, p.fapu_notes);
  EXPECT_EQ(q.camera.image_size, p.camera.image_size);
  EXPECT_DOUBLE_EQ(q.camera.fy, p.camera.fy);
  EXPECT_EQ(q.camera.distortion, p.camera.distortion);
  EXPECT_EQ(q.camera.source, p.camera.source);
  ASSERT_TRUE(q.neutral_pose);
  EXPECT_EQ(q.neutral_pose->translation, p.neutral_pose->translation);
  EXPECT_EQ(q.neutral_pose->rotation, p.neutral_pose->rotation);
  ASSERT_EQ(q.markers.size(), 2u);
  EXPECT_EQ(q.markers[0].feature_point, (FeaturePointId{4, 1}));
  EXPECT_EQ(q.markers[0].image, p.markers[0].image);
  ASSERT_TRUE(q.markers[0].position);
  EXPECT_TRUE(q.markers[0].position->isApprox(*p.markers[0].position));
  EXPECT_FALSE(q.markers[1].position);
  EXPECT_TRUE(q.markers[1].rigid);
  EXPECT_FALSE(is_feature_point(q.markers[1].feature_point));
  ASSERT_EQ(q.fap_gains.size(), 2u);
  EXPECT_DOUBLE_EQ(q.apply_gain(3, 1000), 1000.0);  // 1200 clamped to max
  EXPECT_DOUBLE_EQ(q.apply_gain(3, -10), 0.0);
  EXPECT_DOUBLE_EQ(q.apply_gain(31, 100), 80.0);
  EXPECT_DOUBLE_EQ(q.apply_gain(32, 100), 100.0);
  std::filesystem::remove(path);
}

TEST(ActorProfile, MalformedFilesNameTheField) {
  const std::string good = actor_profile_to_json(sample());
  EXPECT_NO_THROW(actor_profile_from_json(good, "ana.json"));
  auto with = [&](const std::string& from, const std::string& to) {
    std::string t = good;
    const auto at = t.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return t.replace(at, from.size(), to);
  };
  EXPECT_NE(error_of("{ nope").find("not valid JSON"), std::string::npos);
  EXPECT_NE(error_of("[1, 2]").find("expected a JSON object"), std::string::npos);
  EXPECT_NE(error_of(with("rostro-actor-profile", "something")).find("'format'"),
            std::string::npos);
  EXPECT_NE(error_of(with("\"es0\": 63.1", "\"es0\": -1")).find("'fapu.es0' must be positive"),
            std::string::npos);
  EXPECT_NE(error_of(with("\"es0\": 63.1,", "")).find("'fapu.es0' is missing"), std::string::npos);
  EXPECT_NE(error_of(with("\"fp\": \"4.1\"", "\"fp\": \"4.9\"")).find("markers[0].fp"),
            std::string::npos);
  EXPECT_NE(error_of(with("\"tag36h11:0\"", "\"brow_l_in\"")).find("repeats"), std::string::npos);
  EXPECT_NE(error_of(with("\"fap\": \"open_jaw\"", "\"fap\": \"yawn\"")).find("fap_gains[0].fap"),
            std::string::npos);
  EXPECT_NE(error_of(with("\"min\": 0.0", "\"min\": 5000.0")).find("greater than max"),
            std::string::npos);
  EXPECT_NE(
      error_of(with("\"fx\": 1001.5", "\"fx\": \"big\"")).find("'camera.fx' must be a number"),
      std::string::npos);
  EXPECT_NE(error_of(with("\"rigid\": true", "\"rigid\": false")).find("not rigid"),
            std::string::npos);
  EXPECT_THROW(read_actor_profile("/nonexistent/actor.json"), InputError);
}

TEST(ActorProfile, FailedWriteKeepsTheEarlierFile) {
  const auto dir = std::filesystem::path(ROSTRO_BINARY_DIR) / "test_actor_profile_dir";
  std::filesystem::create_directories(dir);
  const auto path = dir / "actor.json";
  write_actor_profile(path, sample());
  EXPECT_THROW(write_actor_profile(dir / "missing" / "actor.json", sample()), InputError);
  EXPECT_EQ(read_actor_profile(path).name, "ana");
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace rostro::calib
