// The seed's 2D method: right values for a still head, what it cannot do, and its guards.
#include <gtest/gtest.h>

#include "calib/actor_calibration.hpp"
#include "facecore/error.hpp"
#include "mapping/fap_mapper.hpp"
#include "mapping/seed2d_mapper.hpp"
#include "tests/support/synthetic_face.hpp"

namespace rostro::mapping {
namespace {

calib::ActorProfile calibrated(const test::SyntheticActor& actor, const tracking::HeadPose& pose) {
  std::mt19937 rng(2);
  std::vector<tracking::TrackedFrame> frames;
  for (int i = 0; i < 5; ++i) frames.push_back(test::render(actor, {}, pose, 0, rng, i));
  return calib::calibrate_actor(frames, actor.camera, test::calibration_options());
}

TEST(Seed2d, StillHeadGivesTheDrivenValues) {
  // Far camera: the seed's method ignores perspective, so it is exact only in the limit.
  const auto actor = test::make_actor(1.0, 1.0, 1.0);
  const auto pose = test::head_pose(0, 0, 0, {0, 0, 3000});
  const Seed2dMapper mapper(calibrated(actor, pose));
  std::mt19937 rng(4);
  auto truth = test::test_expression();
  truth.erase(63);  // the nose tip is the reference: its own FAPs read as 0
  truth.erase(64);
  const FapFrame f = mapper.map(test::render(actor, truth, pose, 0, rng));
  for (const auto& [id, value] : truth) {
    ASSERT_TRUE(f.has(id)) << "FAP " << id;
    EXPECT_NEAR(f.get(id), value, 0.02 * std::abs(value) + 1.0) << fap_info(id).name;
  }
  EXPECT_FALSE(f.has(63));
  EXPECT_FALSE(f.has(49)) << "seed2d estimates no head rotation";
}

TEST(Seed2d, HeadTranslationIsCorrectedByTheNoseTip) {
  const auto actor = test::make_actor(1.0, 1.0, 1.0);
  const auto pose = test::head_pose(0, 0, 0, {0, 0, 3000});
  const Seed2dMapper mapper(calibrated(actor, pose));
  std::mt19937 rng(6);
  const auto moved = test::head_pose(0, 0, 0, {40, -25, 3000});
  const FapFrame f = mapper.map(test::render(actor, {{31, 100}}, moved, 0, rng));
  // Not exact even far away: a sideways move shows the face from a slightly other angle, and
  // the lips (18 mm behind the nose tip) shift against it by parallax (here 0.25 mm).
  EXPECT_NEAR(f.get(31), 100.0, 6.0);
  EXPECT_NEAR(f.get(53), 0.0, 6.0);
}

TEST(Seed2d, HeadRotationBreaksIt) {
  // The documented limitation: a turned head reads as facial motion.
  const auto actor = test::make_actor(1.0, 1.0, 1.0);
  const auto pose = test::head_pose(0, 0, 0);
  const Seed2dMapper mapper(calibrated(actor, pose));
  std::mt19937 rng(8);
  const FapFrame f = mapper.map(test::render(actor, {}, test::head_pose(20, 0, 0), 0, rng));
  EXPECT_GT(std::abs(f.get(53)), 50.0);
}

TEST(Seed2d, NoNoseTipNoFrame) {
  const auto actor = test::make_actor();
  const auto pose = test::head_pose(0, 0, 0);
  const auto profile = calibrated(actor, pose);
  const Seed2dMapper mapper(profile);
  std::mt19937 rng(10);
  auto frame = test::render(actor, {{3, 200}}, pose, 0, rng);
  for (auto& m : frame.markers)
    if (m.marker == "nose_tip") m.valid = false;
  EXPECT_TRUE(mapper.map(frame).mask.none());

  auto without = profile;
  std::erase_if(without.markers,
                [](const calib::NeutralMarker& m) { return m.marker == "nose_tip"; });
  EXPECT_THROW(Seed2dMapper{without}, InputError);
}

TEST(FapMapper, MethodNamesAndTheHierarchySwitch) {
  EXPECT_EQ(parse_method("ceres"), Method::Ceres);
  EXPECT_EQ(parse_method("seed2d"), Method::Seed2d);
  EXPECT_THROW(parse_method("magic"), InputError);

  const auto actor = test::make_actor();
  const auto pose = test::head_pose(0, 0, 0);
  const auto profile = calibrated(actor, pose);
  std::mt19937 rng(12);
  const auto frame = test::render(actor, {{3, 300}, {53, 100}}, pose, 0, rng);
  for (Method method : {Method::Ceres, Method::Seed2d}) {
    MapperOptions plain;
    plain.method = method;
    MapperOptions with = plain;
    with.hierarchy = hierarchy_from_json(
        R"({"rules": [{"target": "thrust_jaw", "source": "open_jaw", "factor": 0.5}]})", "test");
    const FapFrame a = make_fap_mapper(profile, plain)->map(frame);
    const FapFrame b = make_fap_mapper(profile, with)->map(frame);
    EXPECT_FALSE(a.has(14));
    ASSERT_TRUE(b.has(14));
    EXPECT_NEAR(b.get(14), 0.5 * b.get(3), 1e-9);
    EXPECT_NEAR(a.get(3), 300.0, 20.0);
  }
}

}  // namespace
}  // namespace rostro::mapping
