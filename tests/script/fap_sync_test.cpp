// FAP Synchronization's rules (seed004 6.6), each with its layers switched on and off.

#include "script/fap_sync.hpp"

#include <gtest/gtest.h>

#include <numbers>

namespace rostro::script {
namespace {

using speech::fap;
constexpr double kAu = std::numbers::pi / 180.0 * 1e5;

class FapSyncTest : public ::testing::Test {
 protected:
  speech::BehaviourSettings behaviour_ = speech::BehaviourSettings::load_default();
  FapSynchronizer sync_{behaviour_, {3, 4, 5}};
};

TEST_F(FapSyncTest, MouthIsExpressionPlusThreeVisemesOverFour) {
  FapVector s{};
  fap(s, 3) = 200;
  FrameLayers l;
  l.speech = &s;
  l.speech_activity = 1.0;
  fap(l.expression, 3) = 100;
  fap(l.expression_activity, 3) = 1.0;
  EXPECT_DOUBLE_EQ(fap(sync_.merge(l), 3), (100 + 3 * 200) / 4.0);
  // Without speech the expression is whole; without an expression the viseme is.
  l.speech_activity = 0.0;
  fap(s, 3) = 0;
  EXPECT_DOUBLE_EQ(fap(sync_.merge(l), 3), 100);
  fap(s, 3) = 200;
  l.speech_activity = 1.0;
  fap(l.expression, 3) = 0;
  fap(l.expression_activity, 3) = 0;
  EXPECT_DOUBLE_EQ(fap(sync_.merge(l), 3), 200);
}

TEST_F(FapSyncTest, BilabialClosureOverridesTheScriptedExpression) {
  FapVector s{}, v{};
  fap(s, 4) = fap(v, 4) = -50;  // lips pressed for /p/
  FrameLayers l;
  l.speech = &s;
  l.viseme = &v;
  l.speech_activity = 1.0;
  fap(l.expression, 4) = 300;
  fap(l.expression_activity, 4) = 1.0;
  l.closing = 1.0;
  EXPECT_DOUBLE_EQ(fap(sync_.merge(l), 4), -50);
  l.closing = 0.0;
  EXPECT_DOUBLE_EQ(fap(sync_.merge(l), 4), (300 - 3 * 50) / 4.0);
}

TEST_F(FapSyncTest, EyelidsAreQuarterEyeBehaviourThreeQuartersExpression) {
  FrameLayers l;
  fap(l.expression, 19) = 200;
  fap(l.expression_activity, 19) = 1.0;
  l.eyes.lid_irisd = 100;
  l.eyes.lid_activity = 1.0;
  EXPECT_DOUBLE_EQ(fap(sync_.merge(l), 19), 0.75 * 200 + 0.25 * 100);
  fap(l.expression, 19) = 0;
  fap(l.expression_activity, 19) = 0;
  EXPECT_DOUBLE_EQ(fap(sync_.merge(l), 19), 100);
  // A blink shuts the lids whatever the other layers say.
  l.eyes.closure = 1.0;
  EXPECT_DOUBLE_EQ(fap(sync_.merge(l), 19), behaviour_.blink.closed_top_irisd);
  EXPECT_DOUBLE_EQ(fap(sync_.merge(l), 22), behaviour_.blink.closed_bottom_irisd);
}

TEST_F(FapSyncTest, HeadFromGazeIsKeptAndIdleNoiseFadesUnderIt) {
  FrameLayers l;
  l.head.noise.yaw_deg = 2.0;
  EXPECT_DOUBLE_EQ(fap(sync_.merge(l), 49), 2.0 * kAu);
  l.eyes.head_yaw_deg = 6.0;
  l.eyes.head_activity = 1.0;
  EXPECT_DOUBLE_EQ(fap(sync_.merge(l), 49), 6.0 * kAu);  // no noise, no expression on the head
  l.eyes.head_activity = 0.0;
  l.eyes.head_yaw_deg = 0.0;
  l.head.activity = 1.0;
  l.head.action.pitch_deg = 5.0;
  EXPECT_DOUBLE_EQ(fap(sync_.merge(l), 49), 0.0);
  EXPECT_DOUBLE_EQ(fap(sync_.merge(l), 48), 5.0 * kAu);
}

}  // namespace
}  // namespace rostro::script
