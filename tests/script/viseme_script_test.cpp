// The generated viseme script: `rostro speak`'s phonemes, emotions and behaviour written as a
// storyboard that runs to the identical FAP stream, frame for frame, and stays editable.

#include "script/viseme_script.hpp"

#include <gtest/gtest.h>

#include <sstream>

#include "script_test_util.hpp"
#include "speech/animator.hpp"
#include "speech/pipeline.hpp"

namespace rostro::script {
namespace {

struct Spoken {
  speech::PreparedSpeech prepared;
  speech::AnimationOptions options;
  FapStream stream;
};

Spoken speak(const test::Defaults& d, const std::string& text, speech::AnimationOptions options) {
  Spoken s;
  speech::SpeechRequest request;
  request.text = text;
  request.language = "es";
  s.prepared = speech::prepare_speech(request, d.behaviour.default_ramp_s);
  s.options = options;
  const speech::Animator animator(s.prepared.resolution.phonemes, s.prepared.duration_s,
                                  s.prepared.emotions, d.library, d.shapes, d.behaviour, options);
  s.stream = animator.stream("speak");
  return s;
}

FapStream run(const test::Defaults& d, const std::filesystem::path& story) {
  return d.scene(read_storyboard(story, 1))->stream("script");
}

void expect_identical(const FapStream& a, const FapStream& b) {
  EXPECT_EQ(a.header.fps, b.header.fps);
  ASSERT_EQ(a.frames.size(), b.frames.size());
  for (std::size_t k = 0; k < a.frames.size(); ++k) {
    ASSERT_EQ(a.frames[k].mask, b.frames[k].mask) << "frame " << k;
    for (int id = 1; id <= kFapCount; ++id)
      ASSERT_EQ(a.frames[k].get(id), b.frames[k].get(id)) << "frame " << k << " FAP " << id;
  }
}

TEST(VisemeScript, RoundTripsToTheIdenticalFapStream) {
  const test::Defaults d;
  speech::AnimationOptions options;
  options.fps = 30;
  options.seed = 5;
  const Spoken s =
      speak(d, "Hola, {joy 0.7} buenos días. {sadness ramp=0.5s} Hasta pronto.", options);
  ASSERT_FALSE(s.prepared.emotions.empty());
  const auto dir = test::scratch("viseme-roundtrip");
  write_viseme_script(dir / "hola.lua", viseme_script_for(s.prepared, options, "es", "test", ""));
  expect_identical(s.stream, run(d, dir / "hola.lua"));
}

TEST(VisemeScript, RoundTripsWithoutBehaviourAndWithABaseEmotion) {
  const test::Defaults d;
  speech::AnimationOptions options;
  options.blinks = false;
  options.head_motion = false;
  options.base_expression = 2;
  options.base_intensity = 0.4;
  const Spoken s = speak(d, "Mañana, pan y membrillo.", options);
  const auto dir = test::scratch("viseme-plain");
  write_viseme_script(dir / "pan.lua", viseme_script_for(s.prepared, options, "es", "test", ""));
  const FapStream again = run(d, dir / "pan.lua");
  expect_identical(s.stream, again);
  EXPECT_FALSE(again.frames[0].has(49));  // no head motion: no head FAPs, as in rostro speak
}

TEST(VisemeScript, AnEditedScriptMovesTheMouthDifferently) {
  const test::Defaults d;
  speech::AnimationOptions options;
  const Spoken s = speak(d, "Papá", options);
  std::ostringstream text;
  write_viseme_script(text, viseme_script_for(s.prepared, options, "es", "test", ""), ".");
  std::string edited = text.str();
  // An artist turns every open "aa" into a closed "p_b_m".
  for (std::size_t at; (at = edited.find("\"aa\"")) != std::string::npos;)
    edited.replace(at, 4, "\"p_b_m\"");
  ASSERT_NE(edited, text.str());
  const auto dir = test::scratch("viseme-edit");
  const FapStream again = run(d, test::write(dir / "edited.lua", edited));
  ASSERT_EQ(again.frames.size(), s.stream.frames.size());
  double most = 0;
  for (std::size_t k = 0; k < again.frames.size(); ++k)
    most = std::max(most, std::abs(again.frames[k].get(3) - s.stream.frames[k].get(3)));
  EXPECT_GT(most, 50.0);  // open_jaw: the jaw no longer opens for the vowels
}

TEST(VisemeScript, NumbersReadBackExactly) {
  for (double x : {0.0, 0.1, 1.0 / 3.0, 2.0453514739229026, 1e-7, 123456.789})
    EXPECT_EQ(std::stod(exact_number(x)), x);
}

}  // namespace
}  // namespace rostro::script
