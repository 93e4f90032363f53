// Whole scenes: the storyboard (speech, expressions, a look, natural blinks), overlap
// rules and the checks that need speech lengths.

#include "script/scene.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "facecore/error.hpp"
#include "script_test_util.hpp"
#include "speech/audio.hpp"
#include "speech/espeak_synth.hpp"
#include "speech/key_sampler.hpp"

namespace rostro::script {
namespace {

constexpr double kAu = std::numbers::pi / 180.0 * 1e5;

// The time of the frame where FAP `id` is largest.
double peak_time(const FapStream& s, int id) {
  double best = -1e300, when = -1;
  for (const FapFrame& f : s.frames)
    if (f.get(id) > best) {
      best = f.get(id);
      when = f.time_s;
    }
  return when;
}

TEST(Scene, SpanishStoryboardWithJoySurpriseLookAndBlinks) {
  const auto story = test::story(
      "scene-storyboard", "story.lua",
      "storyboard = {\n"
      "  speech = { text = 'Buenos días. Bienvenidos al laboratorio; hoy vamos a ver cómo se "
      "mueve una cara.', lang = 'es' },\n"
      "  expressions = { {'joy', at = 0.5, to = 1.5}, {'surprise', at = 2.0, duration = 0.8} },\n"
      "  eyes = { {'blinks', rate = 30}, {'look', 'left', at = 1.0, duration = 1.0} },\n"
      "}\n");
  const test::Defaults d;
  const auto scene = d.scene(story);
  const FapStream s = scene->stream("t");
  ASSERT_EQ(scene->utterances().size(), 1u);
  const speech::Audio& audio = scene->utterances()[0].speech.audio;
  ASSERT_GT(audio.duration_s(), 3.0);
  EXPECT_EQ(scene->frame_count(), speech::frame_count_for(audio.duration_s(), 25.0));
  EXPECT_EQ(scene->audio().samples, audio.samples);

  const double joy = peak_time(s, 41);  // lift_l_cheek: joy's, no viseme moves it
  EXPECT_GT(joy, 0.5);
  EXPECT_LT(joy, 1.5);
  const double surprise = peak_time(s, 31);  // raise_l_i_eyebrow
  EXPECT_GT(surprise, 2.0);
  EXPECT_LT(surprise, 2.8);

  // The eyes turn to the character's left at 1 s (no saccades: still before).
  EXPECT_EQ(s.frames[24].get(23), 0.0);
  EXPECT_GT(s.frames[28].get(23), 8.0 * kAu);
  EXPECT_GT(s.frames[28].get(24), 8.0 * kAu);
  // ...and the head follows the 20 degree shift a little.
  EXPECT_GT(s.frames[45].get(49) - s.frames[20].get(49), 3.0 * kAu);

  int blinks = 0;
  bool shut = false;
  for (const FapFrame& f : s.frames) {
    const bool now = f.get(19) > 0.8 * d.behaviour.blink.closed_top_irisd;
    blinks += now && !shut;
    shut = now;
  }
  EXPECT_GE(blinks, 1);
}

// A speech item from hand-made visemes: "a" between two silences.
std::string viseme_item(double at) {
  return "{ at = " + std::to_string(at) +
         ", visemes = { {0, 0.2, 'sil'}, {0.2, 0.6, 'aa', 'vowel', word = 0}, {0.6, 0.8, 'sil'} } "
         "}";
}

TEST(Scene, SpeechOverlappingSpeechIsRefused) {
  const auto dir = test::scratch("scene-overlap");
  const test::Defaults d;
  const auto backwards =
      test::write(dir / "backwards.lua", "storyboard = { speech = { " + viseme_item(0) + ", " +
                                             viseme_item(0.8) + ", " + viseme_item(-0) + " } }\n");
  EXPECT_THROW(d.scene(backwards),
               InputError);  // the third starts at 0, before the second: backwards
  const auto after = test::write(dir / "after.lua", "storyboard = { speech = { " + viseme_item(0) +
                                                        ", " + viseme_item(0.8) + " } }\n");
  const auto scene = d.scene(after);
  EXPECT_EQ(scene->frame_count(), 40);  // 1.6 s
  EXPECT_EQ(scene->utterances()[1].first_frame, 20);
  const auto overlap =
      test::write(dir / "overlap.lua", "storyboard = { speech = { " + viseme_item(0) + ", " +
                                           viseme_item(0.5) + " } }\n");
  try {
    d.scene(overlap);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("speech[2]: speech overlaps speech"), std::string::npos)
        << e.what();
  }
}

// A recording with its text is aligned to it (issue 20): the scene lasts as long as the
// recording and its lips close for the m and b of the text.
TEST(Scene, RecordingWithItsTextIsAligned) {
  const auto dir = test::scratch("scene-recording");
  speech::SynthOptions voice;
  voice.voice = "es+f3";
  voice.rate_wpm = 150;
  const speech::Synthesis recorded = speech::synthesize("Buenos días, mamá.", voice);
  speech::write_wav(dir / "take.wav", recorded.audio);
  const auto story = test::write(
      dir / "story.lua",
      "storyboard = { speech = { sound = \"take.wav\", text = \"Buenos días, mamá.\" } }\n");
  const test::Defaults d;
  const auto scene = d.scene(story);
  EXPECT_EQ(scene->frame_count(),
            static_cast<long>(std::ceil(recorded.audio.duration_s() * 25.0 - 1e-9)));
  int closed = 0;
  for (long k = 0; k < scene->frame_count(); ++k)
    closed += d.shapes.lips_closed(scene->frame(k).values);
  EXPECT_GE(closed, 2);  // b of buenos, m of mamá
}

// The whole scene's phonemes (for mouth cues): each utterance at its start, silence between
// and after, contiguous from 0 to the scene's end.
TEST(Scene, PhonemesCoverTheSceneWithSilenceBetweenUtterances) {
  const auto dir = test::scratch("scene-phonemes");
  const test::Defaults d;
  const auto story =
      test::write(dir / "two.lua", "storyboard = { duration = 3, speech = { " + viseme_item(0) +
                                       ", " + viseme_item(1.2) + " } }\n");
  const auto scene = d.scene(story);
  const auto phonemes = scene->phonemes();
  ASSERT_FALSE(phonemes.empty());
  EXPECT_DOUBLE_EQ(phonemes.front().start_s, 0.0);
  EXPECT_DOUBLE_EQ(phonemes.back().end_s, scene->duration_s());
  for (std::size_t k = 1; k < phonemes.size(); ++k)
    EXPECT_NEAR(phonemes[k].start_s, phonemes[k - 1].end_s, 1e-9) << k;
  int vowels = 0;
  for (const auto& p : phonemes) {
    if (p.cls != speech::PhonemeClass::Vowel) continue;
    ++vowels;
    EXPECT_TRUE(std::abs(p.start_s - 0.2) < 1e-9 || std::abs(p.start_s - 1.4) < 1e-9) << p.start_s;
  }
  EXPECT_EQ(vowels, 2);
}

TEST(Scene, BadFrameRateIsNamed) {
  const test::Defaults d;
  Storyboard board;
  board.duration = 1.0;
  SceneOptions options;
  options.fps = 0;
  try {
    Scene(board, {}, d.library, d.shapes, d.behaviour, options);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("SceneOptions::fps = 0"), std::string::npos) << e.what();
  }
}

TEST(Scene, TwoExpressionsAtOnceShareTheirWeight) {
  const auto dir = test::scratch("scene-two");
  const test::Defaults d;
  const auto story = test::write(dir / "two.lua",
                                 "storyboard = { head = { {'still'} }, expressions = { {'joy', at "
                                 "= 0, duration = 2, ramp = 0},"
                                 " {'surprise', at = 0, duration = 2, ramp = 0} } }\n");
  const FapStream s = d.scene(story)->stream("t");
  const FapVector joy = speech::low_level_vector(d.library.expression(1));
  const FapVector surprise = speech::low_level_vector(d.library.expression(6));
  // Weights 1 + 1 are scaled to 1/2 each: the mean of the two expressions.
  EXPECT_DOUBLE_EQ(s.frames[10].get(41), speech::fap(joy, 41) / 2);
  EXPECT_DOUBLE_EQ(s.frames[10].get(31), speech::fap(surprise, 31) / 2);
  EXPECT_FALSE(s.frames[10].has(49));  // a still head all through: no head FAPs at all
}

TEST(Scene, ScriptedCloseAndBlinkTakeTheLarger) {
  const auto dir = test::scratch("scene-close");
  const test::Defaults d;
  const auto story = test::write(dir / "close.lua",
                                 "storyboard = { eyes = { {'half_close', at = 0, duration = 2, "
                                 "ramp = 0}, {'blink', at = 1} } }\n");
  const FapStream s = d.scene(story)->stream("t");
  const double closed = d.behaviour.blink.closed_top_irisd;
  EXPECT_NEAR(s.frames[10].get(19), 0.5 * closed, 1e-9);
  double most = 0;
  for (int k = 25; k < 33; ++k) most = std::max(most, s.frames[k].get(19));
  EXPECT_NEAR(most, closed, 1e-9);  // the blink shuts the half-closed eyes fully
}

TEST(Scene, HeadActionsMoveTheirAxes) {
  const auto dir = test::scratch("scene-head");
  const test::Defaults d;
  const auto story = test::write(
      dir / "head.lua",
      "storyboard = { head = { {'still'}, {'nod', at = 0, duration = 1, amplitude = 10},\n"
      "  {'shake', at = 1, duration = 1}, {'tilt', 'left', at = 2}, {'turn', 'right', at = 4, "
      "duration = 1} } }\n");
  const FapStream s = d.scene(story)->stream("t");
  EXPECT_NEAR(s.frames[12].get(48), 10.0 * kAu, 0.05 * kAu);  // the bottom of the nod
  EXPECT_NEAR(s.frames[12].get(49), 0.0, 1e-9);
  double shake = 0;
  for (int k = 25; k < 50; ++k) shake = std::max(shake, std::abs(s.frames[k].get(49)));
  EXPECT_GT(shake, 4.0 * kAu);
  EXPECT_NEAR(s.frames[70].get(50), -8.0 * kAu, 1e-6);    // tilted to the left
  EXPECT_NEAR(s.frames[112].get(49), -20.0 * kAu, 1e-6);  // turned right
}

}  // namespace
}  // namespace rostro::script
