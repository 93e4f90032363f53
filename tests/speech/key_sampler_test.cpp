// Frame sampling on the audio clock and the bilabial closure guarantee.

#include <gtest/gtest.h>

#include "facecore/expression_library.hpp"
#include "speech/animator.hpp"
#include "speech/key_sampler.hpp"
#include "speech/key_shapes.hpp"
#include "speech/pipeline.hpp"
#include "speech_test_util.hpp"

namespace rostro::speech {
namespace {

TEST(KeySampler, FrameCountFollowsTheAudioDuration) {
  EXPECT_EQ(frame_count_for(2.0, 25.0), 50);
  EXPECT_EQ(frame_count_for(2.001, 25.0), 51);
  EXPECT_EQ(frame_count_for(1.95, 30.0), 59);
  EXPECT_EQ(frame_count_for(0.0, 25.0), 0);
  for (double d : {0.3, 1.234567, 17.77, 61.03})
    for (double fps : {24.0, 25.0, 29.97, 30.0, 60.0})
      EXPECT_NEAR(static_cast<double>(frame_count_for(d, fps)), d * fps, 1.0)
          << d << " s at " << fps;
}

class Closure : public ::testing::Test {
 protected:
  void SetUp() override {
    library_ = ExpressionLibrary::load_default();
    shapes_ = std::make_unique<KeyShapes>(KeyShapes::load_default(library_));
    behaviour_ = BehaviourSettings::load_default();
  }
  // True when some frame within half a frame of [start, end] shows closed lips.
  bool closes(const Animator& a, const Phoneme& p, double fps) {
    for (long k = 0; k < a.frame_count(); ++k) {
      const double t = static_cast<double>(k) / fps;
      if (t < p.start_s - 0.5 / fps - 1e-9 || t > p.end_s + 0.5 / fps + 1e-9) continue;
      if (shapes_->lips_closed(low_level_vector(a.frame(k)))) return true;
    }
    return false;
  }
  ExpressionLibrary library_;
  std::unique_ptr<KeyShapes> shapes_;
  BehaviourSettings behaviour_;
};

TEST_F(Closure, VisemeOneIsClosedAndCarriesItsClosureIntoContext) {
  EXPECT_TRUE(shapes_->lips_closed(shapes_->viseme(1)))
      << "data/visemes.json p_b_m must close the lips";
  const auto p = test::phonemes({{"_", 's', 0, 100},
                                 {"a", 'v', 10, 100},
                                 {"m", 'c', 1, 60},
                                 {"u", 'v', 14, 100},
                                 {"_", 's', 0, 100}});
  for (const Key& k : plan_keys(p)) {
    if (k.consonant == 2) {
      EXPECT_TRUE(shapes_->lips_closed(shapes_->shape(k, p))) << key_label(k, p);
    }
  }
}

TEST_F(Closure, EveryBilabialClosesEvenWhenShortAndUnderAnOpenMouthedEmotion) {
  // Short /p b m/ in every position: after a vowel, after a consonant, word-initial after
  // silence, in clusters, and 15 ms long, between frames.
  const auto p = test::phonemes({{"_", 's', 0, 130},
                                 {"p", 'c', 1, 23},
                                 {"a", 'v', 10, 87},
                                 {"m", 'c', 1, 17},
                                 {"a", 'v', 10, 71},
                                 {"s", 'c', 7, 64},
                                 {"p", 'c', 1, 15},
                                 {"e", 'v', 11, 93},
                                 {"r", 'c', 9, 41},
                                 {"b", 'c', 1, 19},
                                 {"o", 'v', 13, 77},
                                 {"_", 's', 0, 90},
                                 {"m", 'c', 1, 33},
                                 {"b", 'c', 1, 21},
                                 {"i", 'v', 12, 66},
                                 {"k", 'c', 5, 50},
                                 {"m", 'c', 1, 12},
                                 {"_", 's', 0, 150}});
  const double duration = p.back().end_s;
  int forced = 0;  // the cross-fade alone misses some of these short closures
  for (double fps : {25.0, 30.0}) {
    for (int emotion : {0, 1, 6}) {  // neutral, joy, surprise (jaw open)
      AnimationOptions o;
      o.fps = fps;
      o.base_expression = emotion;
      o.blinks = o.saccades = o.head_motion = false;
      const Animator a(p, duration, {}, library_, *shapes_, behaviour_, o);
      forced += a.forced_closures();
      for (const Phoneme& ph : p) {
        if (ph.closes_lips) {
          EXPECT_TRUE(closes(a, ph, fps))
              << ph.symbol << " at " << ph.start_s << " s, " << fps << " fps, emotion " << emotion;
        }
      }
    }
  }
  EXPECT_GT(forced, 0);
}

TEST_F(Closure, EveryBilabialClosesInSynthesisedSpeech) {
  const std::pair<const char*, const char*> samples[] = {
      {"es",
       "{surprise}Pablo bebe mucha agua, mamá compra pan y embutidos. Bomba, ambos, hombre, ¿por "
       "qué?"},
      {"pt",
       "{joy}Bom dia! O pombo bebeu um pouco de sumo, também comprámos pão. Ambos, embora, "
       "sempre."},
      {"en",
       "{fear 0.7}Bob's big brown bag bumped my lamp. Maybe, probably, members, plumber, emphasis, "
       "mumble."}};
  for (const auto& [lang, text] : samples) {
    SpeechRequest r;
    r.language = lang;
    r.text = text;
    const PreparedSpeech prepared = prepare_speech(r, 0.3);
    AnimationOptions o;
    const Animator a(prepared.resolution.phonemes, prepared.duration_s, prepared.emotions, library_,
                     *shapes_, behaviour_, o);
    int bilabials = 0;
    for (const Phoneme& ph : a.phonemes()) {
      if (!ph.closes_lips) continue;
      ++bilabials;
      EXPECT_TRUE(closes(a, ph, o.fps))
          << lang << ": " << ph.symbol << " at " << ph.start_s << " s";
    }
    EXPECT_GT(bilabials, 10) << lang;
  }
}

TEST_F(Closure, ClosureIsNotForcedWhenTheCrossFadeAlreadyCloses) {
  const auto p = test::phonemes({{"_", 's', 0, 200},
                                 {"a", 'v', 10, 150},
                                 {"m", 'c', 1, 200},
                                 {"a", 'v', 10, 150},
                                 {"_", 's', 0, 200}});
  AnimationOptions o;
  const Animator a(p, p.back().end_s, {}, library_, *shapes_, behaviour_, o);
  EXPECT_EQ(a.forced_closures(), 0);
}

}  // namespace
}  // namespace rostro::speech
