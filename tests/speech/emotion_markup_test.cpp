// Emotion markup: {emotion [intensity] [ramp=T]} and the seed's <Emo_X> control words.

#include <gtest/gtest.h>

#include "facecore/error.hpp"
#include "speech/emotion_markup.hpp"
#include "speech/phoneme_table.hpp"
#include "speech/pipeline.hpp"

namespace rostro::speech {
namespace {

TEST(EmotionMarkup, PlainTextPassesThrough) {
  const MarkedText m = parse_emotion_markup("Hola, buenos días.");
  EXPECT_EQ(m.clean, "Hola, buenos días.");
  EXPECT_TRUE(m.tags.empty());
}

TEST(EmotionMarkup, BraceTagsWithIntensityAndRamp) {
  const MarkedText m = parse_emotion_markup(
      "{joy}Hola, {sadness 0.6 ramp=0.5s}días {anger 40% ramp=250ms}sí{neutral}");
  EXPECT_EQ(m.clean, "Hola, días sí");
  ASSERT_EQ(m.tags.size(), 4u);
  EXPECT_EQ(m.tags[0].expression, 1);
  EXPECT_DOUBLE_EQ(m.tags[0].intensity, 1.0);
  EXPECT_LT(m.tags[0].ramp_s, 0.0);  // default ramp
  EXPECT_EQ(m.tags[0].position, 0u);
  EXPECT_EQ(m.tags[1].expression, 2);
  EXPECT_DOUBLE_EQ(m.tags[1].intensity, 0.6);
  EXPECT_DOUBLE_EQ(m.tags[1].ramp_s, 0.5);
  EXPECT_EQ(m.tags[1].position, 6u);
  EXPECT_EQ(m.tags[2].expression, 3);
  EXPECT_DOUBLE_EQ(m.tags[2].intensity, 0.4);
  EXPECT_DOUBLE_EQ(m.tags[2].ramp_s, 0.25);
  EXPECT_EQ(m.tags[2].position, 11u);  // code points: "días " counts í once
  EXPECT_EQ(m.tags[3].expression, 0);
  EXPECT_EQ(m.tags[3].position, 13u);
}

TEST(EmotionMarkup, SeedControlWordsAreAccepted) {
  const MarkedText m = parse_emotion_markup(
      "<Emo_Reír>Hola <Emo_Tristeza>adiós <Emo_Reflejo del disgusto>no <Emo_Sorpresa>ah "
      "<Emo_NEUTRAL>"
      "<Emo_Reir><emocion_Miedo><Emo_Enojo><Emo_FIN>");
  EXPECT_EQ(m.clean, "Hola adiós no ah ");
  std::vector<int> got;
  for (const auto& t : m.tags) got.push_back(t.expression);
  EXPECT_EQ(got, (std::vector<int>{1, 2, 5, 6, 0, 1, 4, 3, 0}));
}

TEST(EmotionMarkup, PortugueseAndEnglishNamesAndLiteralBraces) {
  EXPECT_EQ(emotion_from_name("Alegría"), 1);
  EXPECT_EQ(emotion_from_name("SURPRESA"), 6);
  EXPECT_EQ(emotion_from_name("raiva"), 3);
  EXPECT_EQ(emotion_from_name("medo"), 4);
  EXPECT_EQ(emotion_from_name("nojo"), 5);
  EXPECT_EQ(emotion_from_name("bored"), -1);
  const MarkedText m = parse_emotion_markup("a {{b}} c");
  EXPECT_EQ(m.clean, "a {b} c");
  EXPECT_TRUE(m.tags.empty());
}

TEST(EmotionMarkup, ErrorsNameTheColumnAndTheProblem) {
  const auto message = [](const std::string& text) {
    try {
      parse_emotion_markup(text);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("Hola {joyy}").find("column 6: unknown emotion 'joyy'"), std::string::npos)
      << message("Hola {joyy}");
  EXPECT_NE(message("Hola {joy").find("column 6: unclosed '{'"), std::string::npos);
  EXPECT_NE(message("{joy 1.5}").find("bad intensity '1.5'"), std::string::npos);
  EXPECT_NE(message("{joy 120%}").find("bad intensity"), std::string::npos);
  EXPECT_NE(message("{joy ramp=fast}").find("bad ramp"), std::string::npos);
  EXPECT_NE(message("{joy 0.5 0.7}").find("unexpected '0.7'"), std::string::npos);
  EXPECT_NE(message("{}").find("empty emotion tag"), std::string::npos);
  EXPECT_NE(message("a } b").find("column 3"), std::string::npos);
  EXPECT_NE(message("días <Emo_Bostezo>").find("column 6: '<Emo_Bostezo>' is not an emotion"),
            std::string::npos);
  EXPECT_NE(message("<Emo_Reír").find("unclosed '<'"), std::string::npos);
}

TEST(EmotionMarkup, TagTimeIsTheEndOfThePreviousWord) {
  const LanguageTable table = LanguageTable::for_language("es");
  // "Hola amigo": hola = o l a (position 0), amigo (position 5).
  std::vector<RawPhoneme> raw{{"o", 0.0, 0.1, 0},  {"l", 0.1, 0.15, 0}, {"a", 0.15, 0.25, 0},
                              {"_", 0.25, 0.4, 4}, {"a", 0.4, 0.5, 5},  {"m", 0.5, 0.55, 5},
                              {"i", 0.55, 0.6, 5}, {"_", 0.6, 0.7, 10}};
  EXPECT_DOUBLE_EQ(tag_time(0, raw, table), 0.0);
  EXPECT_DOUBLE_EQ(tag_time(5, raw, table), 0.25);
  EXPECT_DOUBLE_EQ(tag_time(10, raw, table), 0.6);
}

}  // namespace
}  // namespace rostro::speech
