// The GDL behaviours one at a time: look and return, pursuit, the head's share of a large
// gaze shift, the lids following vertical gaze, saccade styles, blinks in a window.

#include "script/eye_behaviour.hpp"

#include <gtest/gtest.h>

namespace rostro::script {
namespace {

constexpr double kFps = 100.0;

EyeAction look(Direction target, double at, double end) {
  EyeAction a;
  a.kind = EyeKind::Look;
  a.at = at;
  a.end = end;
  a.path = {target};
  return a;
}

class EyeBehaviourTest : public ::testing::Test {
 protected:
  speech::BehaviourSettings settings_ = speech::BehaviourSettings::load_default();
};

TEST_F(EyeBehaviourTest, SmallLookIsAllEyesAndReturnsToTheCamera) {
  const EyeBehaviour eyes({look({8, 0, 0}, 0.5, 1.5)}, 250, kFps, settings_, 1);
  EXPECT_EQ(eyes.frame(40).yaw_deg, 0.0);
  EXPECT_NEAR(eyes.frame(100).yaw_deg, 8.0, 1e-9);  // within 10 degrees the head stays
  EXPECT_EQ(eyes.frame(100).head_yaw_deg, 0.0);
  EXPECT_NEAR(eyes.frame(200).yaw_deg, 0.0, 1e-9);  // back after the look ends
}

TEST_F(EyeBehaviourTest, LargeShiftTurnsTheHeadWhileTheGazeStaysOnTarget) {
  const EyeBehaviour eyes({look({30, 0, 0}, 0.0, kOpenEnd)}, 200, kFps, settings_, 1);
  const EyeFrame& f = eyes.frame(190);
  const double head = EyeBehaviour::kHeadShare * (30 - EyeBehaviour::kHeadFreeDeg);
  EXPECT_NEAR(f.head_yaw_deg, head, 0.01);
  EXPECT_NEAR(f.yaw_deg + f.head_yaw_deg, 30.0, 1e-9);
  EXPECT_GT(eyes.frame(15).yaw_deg, eyes.frame(190).yaw_deg);  // eyes lead, head lags
  EXPECT_DOUBLE_EQ(f.head_activity, 1.0);
}

TEST_F(EyeBehaviourTest, PursuitFollowsItsPathAndLidsFollowTheEyesDown) {
  EyeAction p;
  p.kind = EyeKind::Pursuit;
  p.at = 0.0;
  p.end = 2.0;
  p.path = {{-8, 0, 0}, {0, 8, 0}, {8, 0, 0}};
  const EyeBehaviour eyes({p}, 300, kFps, settings_, 1);
  EXPECT_NEAR(eyes.frame(50).yaw_deg, -4.0, 1e-9);  // a quarter of the way: between points
  EXPECT_NEAR(eyes.frame(50).pitch_deg, 4.0, 1e-9);
  EXPECT_NEAR(eyes.frame(100).pitch_deg, 8.0, 1e-9);
  EXPECT_NEAR(eyes.frame(100).lid_irisd, 8.0 * EyeBehaviour::kLidPerDegreeDown, 1e-9);
  EXPECT_NEAR(eyes.frame(250).yaw_deg, 8.0, 1e-9);  // it stays on the last point
}

TEST_F(EyeBehaviourTest, ThinkingSaccadesDriftUpAndAside) {
  EyeAction talking;
  talking.kind = EyeKind::Saccades;
  EyeAction thinking = talking;
  thinking.style = "thinking";
  const EyeBehaviour a({talking}, 3000, kFps, settings_, 4);
  const EyeBehaviour b({thinking}, 3000, kFps, settings_, 4);
  double pitch_a = 0, pitch_b = 0;
  for (long k = 0; k < 3000; ++k) {
    pitch_a += a.frame(k).pitch_deg;
    pitch_b += b.frame(k).pitch_deg;
  }
  EXPECT_LT(pitch_b / 3000, pitch_a / 3000 - 3.0);  // up is negative pitch
}

TEST_F(EyeBehaviourTest, NaturalBlinksStayInTheirWindow) {
  EyeAction blinks;
  blinks.kind = EyeKind::Blinks;
  blinks.at = 10.0;
  blinks.end = 20.0;
  blinks.rate_per_min = 30;
  const EyeBehaviour eyes({blinks}, 3000, kFps, settings_, 2);
  double outside = 0, inside = 0;
  for (long k = 0; k < 3000; ++k) {
    double& most = k >= 1000 && k < 2000 ? inside : outside;
    most = std::max(most, eyes.frame(k).closure);
  }
  EXPECT_EQ(outside, 0.0);
  EXPECT_GT(inside, 0.9);
}

}  // namespace
}  // namespace rostro::script
