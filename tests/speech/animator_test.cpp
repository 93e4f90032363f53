// Mixing visemes with emotions, eyes and head; the switches; seeding.

#include <gtest/gtest.h>

#include "facecore/error.hpp"
#include "facecore/expression_library.hpp"
#include "speech/animator.hpp"
#include "speech/key_shapes.hpp"
#include "speech_test_util.hpp"

namespace rostro::speech {
namespace {

class AnimatorTest : public ::testing::Test {
 protected:
  void SetUp() override {
    library_ = ExpressionLibrary::load_default();
    shapes_ = std::make_unique<KeyShapes>(KeyShapes::load_default(library_));
    behaviour_ = BehaviourSettings::load_default();
    phonemes_ = test::phonemes({{"_", 's', 0, 300}, {"a", 'v', 10, 360}, {"_", 's', 0, 340}});
  }
  Animator make(const AnimationOptions& o, std::vector<EmotionEvent> emotions = {}) {
    return Animator(phonemes_, 1.0, std::move(emotions), library_, *shapes_, behaviour_, o);
  }
  ExpressionLibrary library_;
  std::unique_ptr<KeyShapes> shapes_;
  BehaviourSettings behaviour_;
  std::vector<Phoneme> phonemes_;
};

TEST_F(AnimatorTest, MouthMixesExpressionAndVisemeOneToThree) {
  AnimationOptions o;
  o.blinks = o.saccades = o.head_motion = false;
  o.base_expression = 1;  // joy, full intensity
  const Animator a = make(o);
  const long k = 12;  // t = 0.48 s: the centre of "a"
  const FapVector v = a.viseme_part(k);
  EXPECT_DOUBLE_EQ(fap(v, 3), fap(shapes_->viseme(10), 3));
  const FapFrame f = a.frame(k);
  const FapVector joy = low_level_vector(library_.expression(1));
  for (int id : {3, 6, 12, 53, 59})
    EXPECT_NEAR(f.get(id), (fap(joy, id) + 3.0 * fap(v, id)) / 4.0, 1e-9) << fap_info(id).name;
  // Eyelids, brows and cheeks come from the expression.
  for (int id : {19, 21, 33, 41}) EXPECT_NEAR(f.get(id), fap(joy, id), 1e-9) << fap_info(id).name;
}

TEST_F(AnimatorTest, NeutralLeavesThePureVisemeAndEmotionRamps) {
  AnimationOptions o;
  o.blinks = o.saccades = o.head_motion = false;
  const Animator plain = make(o);
  EXPECT_NEAR(plain.frame(12).get(3), fap(shapes_->viseme(10), 3), 1e-9);
  EXPECT_EQ(plain.frame(0).get(3), 0.0);  // silence: neutral face
  // Surprise at 0.5 intensity ramping over 0.2 s from t = 0.18.
  const Animator a = make(o, {{0.18, 6, 0.5, 0.2}});
  const FapVector surprise = low_level_vector(library_.expression(6));
  EXPECT_NEAR(a.frame(4).get(31), 0.0, 1e-9);                            // t = 0.16
  EXPECT_NEAR(a.frame(7).get(31), 0.5 * 0.5 * fap(surprise, 31), 1e-9);  // t = 0.28: half way
  EXPECT_NEAR(a.frame(20).get(31), 0.5 * fap(surprise, 31), 1e-9);       // t = 0.8: reached
}

TEST_F(AnimatorTest, SwitchesTurnBehaviourOffAndSeedsRepeat) {
  AnimationOptions off;
  off.blinks = off.saccades = off.head_motion = false;
  const Animator quiet = make(off);
  for (long k = 0; k < quiet.frame_count(); ++k) {
    const FapFrame f = quiet.frame(k);
    EXPECT_FALSE(f.has(48));
    EXPECT_FALSE(f.has(23));
    EXPECT_EQ(f.get(19), 0.0);
  }
  // Ten seconds with everything on: the head moves, eyes move, and at least one blink closes.
  phonemes_ = test::phonemes({{"_", 's', 0, 10000}});
  AnimationOptions on;
  on.seed = 7;
  const Animator a(phonemes_, 10.0, {}, library_, *shapes_, behaviour_, on);
  const Animator b(phonemes_, 10.0, {}, library_, *shapes_, behaviour_, on);
  on.seed = 8;
  const Animator c(phonemes_, 10.0, {}, library_, *shapes_, behaviour_, on);
  bool blink = false, gaze = false, head = false, differs = false;
  for (long k = 0; k < a.frame_count(); ++k) {
    const FapFrame fa = a.frame(k);
    EXPECT_EQ(fa, b.frame(k));
    differs |= fa.get(49) != c.frame(k).get(49);
    blink |= fa.get(19) >= behaviour_.blink.closed_top_irisd - 1e-9;
    gaze |= fa.get(23) != 0.0;
    head |= std::abs(fa.get(49)) > 100.0;
    EXPECT_LT(std::abs(fa.get(49)), behaviour_.head.yaw_deg * 1745.4 + 1.0);
  }
  EXPECT_TRUE(blink);
  EXPECT_TRUE(gaze);
  EXPECT_TRUE(head);
  EXPECT_TRUE(differs);
}

TEST_F(AnimatorTest, BlinkIntervalsLookNatural) {
  const auto track = blink_track(25 * 120, 25.0, behaviour_.blink, 3);
  int blinks = 0;
  for (std::size_t k = 1; k < track.size(); ++k) blinks += track[k] >= 1.0 && track[k - 1] < 1.0;
  // About one every 3.6 s over two minutes: between 20 and 50, never two within a second.
  EXPECT_GT(blinks, 20);
  EXPECT_LT(blinks, 50);
}

TEST_F(AnimatorTest, HighLevelFapsCarryTheVisemeBlend) {
  AnimationOptions o;
  o.high_level = true;
  const Animator a = make(o);
  const FapFrame f = a.frame(12);
  EXPECT_TRUE(f.has(1));
  EXPECT_TRUE(f.has(2));
  EXPECT_TRUE(f.viseme.select1 == 10 || f.viseme.select2 == 10);
}

TEST_F(AnimatorTest, BadOptionIsNamedInOneLine) {
  EXPECT_NO_THROW(AnimationOptions{}.validate());
  AnimationOptions o;
  o.fps = 0;
  try {
    make(o);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "AnimationOptions::fps = 0: should be > 0");
  }
  o = {};
  o.base_intensity = 1.5;
  EXPECT_THROW(make(o), InputError);
}

}  // namespace
}  // namespace rostro::speech
