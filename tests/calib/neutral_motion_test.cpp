#include "calib/neutral_motion.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace rostro::calib {
namespace {

// A face of eight markers, about 100 px across; `jaw` moves the chin down by that many px.
tracking::TrackedFrame face(long index, double jaw, double turn_deg, double scale,
                            cv::Point2d shift, std::mt19937& rng, double noise_px) {
  const std::vector<std::pair<std::string, cv::Point2d>> neutral = {
      {"brow_l", {-40, -50}}, {"brow_r", {40, -50}},  {"eye_l", {-30, -30}}, {"eye_r", {30, -30}},
      {"nose", {0, 0}},       {"mouth_l", {-25, 30}}, {"mouth_r", {25, 30}}, {"chin", {0, 60}}};
  std::normal_distribution<double> n(0, noise_px);
  const double a = turn_deg * M_PI / 180, c = std::cos(a), s = std::sin(a);
  tracking::TrackedFrame f;
  f.frame = index;
  for (auto [id, p] : neutral) {
    if (id == "chin") p.y += jaw;
    tracking::MarkerObservation m;
    m.marker = id;
    m.position = shift + scale * cv::Point2d(c * p.x - s * p.y, s * p.x + c * p.y) +
                 cv::Point2d(n(rng), n(rng));
    m.valid = true;
    f.markers.push_back(m);
  }
  return f;
}

TEST(NeutralMotion, AStillFaceWithTrackingNoiseIsStill) {
  std::mt19937 rng(1);
  std::vector<tracking::TrackedFrame> frames;
  for (long i = 0; i < 25; ++i) frames.push_back(face(i, 0, 0, 1, {320, 240}, rng, 0.3));
  const auto motion = measure_neutral_motion(frames);
  ASSERT_TRUE(motion);
  EXPECT_LT(motion->displacement_px, 1.0);  // 0.3 px noise per axis
  EXPECT_EQ(neutral_motion_warning(motion), "");
}

TEST(NeutralMotion, TheHeadMovingAsAWholeIsTakenOut) {
  std::mt19937 rng(2);
  std::vector<tracking::TrackedFrame> frames;
  for (int i = 0; i < 25; ++i) {  // sway, roll and a step toward the camera
    const double t = i;
    frames.push_back(face(i, 0, 0.4 * t, 1 + 0.004 * t, {320 + 2 * t, 240 - t}, rng, 0.3));
  }
  EXPECT_EQ(neutral_motion_warning(measure_neutral_motion(frames)), "");
}

TEST(NeutralMotion, AnOpeningJawIsNamed) {
  std::mt19937 rng(3);
  std::vector<tracking::TrackedFrame> frames;
  for (int i = 0; i < 25; ++i) frames.push_back(face(i, 0.4 * i, 0, 1, {320, 240}, rng, 0.3));
  const auto motion = measure_neutral_motion(frames);
  ASSERT_TRUE(motion);
  EXPECT_EQ(motion->marker, "chin");
  const std::string warning = neutral_motion_warning(motion);
  EXPECT_NE(warning.find("'chin'"), std::string::npos) << warning;
}

TEST(NeutralMotion, TooLittleToCompareIsNoMeasure) {
  std::mt19937 rng(4);
  EXPECT_FALSE(measure_neutral_motion({face(0, 0, 0, 1, {0, 0}, rng, 0)}));
  auto sparse = face(1, 0, 0, 1, {0, 0}, rng, 0);
  sparse.markers.resize(3);
  EXPECT_FALSE(measure_neutral_motion({sparse, sparse, sparse}));
  EXPECT_EQ(neutral_motion_warning(std::nullopt), "");
}

}  // namespace
}  // namespace rostro::calib
