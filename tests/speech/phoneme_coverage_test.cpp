// Every phoneme espeak-ng emits for es, pt (Brazil, Portugal) and en on a varied text is in
// the language table; an unknown phoneme is reported and kept in the timeline.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "facecore/error.hpp"
#include "speech/espeak_synth.hpp"
#include "speech/phoneme_table.hpp"
#include "speech/pipeline.hpp"

namespace rostro::speech {
namespace {

std::string sample_text(const std::string& base) {
  std::ifstream in(std::filesystem::path(ROSTRO_SPEECH_TEXTS) / (base + ".txt"));
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

class Coverage : public ::testing::TestWithParam<const char*> {};

TEST_P(Coverage, EspeakPhonemesAreAllInTheTable) {
  const std::string voice = GetParam();
  const LanguageTable table = LanguageTable::for_language(voice);
  const std::string text = sample_text(table.language());
  ASSERT_FALSE(text.empty());
  const Synthesis s = synthesize(text, SynthOptions{voice, 0, -1});
  ASSERT_GT(s.phonemes.size(), 200u);
  const Resolution r = resolve(s.phonemes, table);
  EXPECT_TRUE(r.unknown.empty()) << voice << ": " << describe_unknown(r.unknown, 50);
  // The timeline is contiguous and ends with the audio.
  for (std::size_t i = 1; i < r.phonemes.size(); ++i)
    EXPECT_DOUBLE_EQ(r.phonemes[i - 1].end_s, r.phonemes[i].start_s);
  EXPECT_NEAR(r.phonemes.back().end_s, s.audio.duration_s(), 1e-9);
}

INSTANTIATE_TEST_SUITE_P(Voices, Coverage,
                         ::testing::Values("es", "es-419", "pt-br", "pt-pt", "en", "en-us"));

TEST(PhonemeTable, UnknownPhonemeIsReportedAndKept) {
  const LanguageTable table = LanguageTable::for_language("es");
  std::vector<RawPhoneme> raw{{"_", 0.0, 0.1, -1},
                              {"o", 0.1, 0.2, 0},
                              {"QQ", 0.2, 0.3, 0},
                              {"a", 0.3, 0.4, 0},
                              {"_", 0.4, 0.6, -1}};
  const Resolution r = resolve(raw, table);
  ASSERT_EQ(r.unknown.size(), 1u);
  EXPECT_EQ(r.unknown[0].symbol, "QQ");
  EXPECT_DOUBLE_EQ(r.unknown[0].start_s, 0.2);
  ASSERT_EQ(r.phonemes.size(), 5u);
  EXPECT_EQ(r.phonemes[2].symbol, "QQ");
  EXPECT_FALSE(r.phonemes[2].known);
  EXPECT_NE(describe_unknown(r.unknown).find("'QQ' at 0.20 s"), std::string::npos);
}

TEST(PhonemeTable, DiphthongsSplitIntoEqualPartsAndSilencesMerge) {
  const LanguageTable table = LanguageTable::for_language("en");
  std::vector<RawPhoneme> raw{
      {"_:", 0.0, 0.1, -1}, {"_", 0.1, 0.15, -1}, {"aI@", 0.15, 0.45, 0}, {"_", 0.45, 0.5, -1}};
  const Resolution r = resolve(raw, table);
  ASSERT_EQ(r.phonemes.size(), 5u);
  EXPECT_EQ(r.phonemes[0].cls, PhonemeClass::Silence);
  EXPECT_DOUBLE_EQ(r.phonemes[0].end_s, 0.15);
  EXPECT_EQ(r.phonemes[1].symbol, "a");
  EXPECT_NEAR(r.phonemes[1].duration(), 0.1, 1e-12);
  EXPECT_EQ(r.phonemes[3].symbol, "@");
  EXPECT_DOUBLE_EQ(r.phonemes[3].end_s, 0.45);
}

TEST(PhonemeTable, BilabialsCloseTheLipsInEveryLanguage) {
  for (const char* lang : {"es", "pt", "en"}) {
    const LanguageTable table = LanguageTable::for_language(lang);
    for (const char* s : {"p", "b", "m"}) {
      ASSERT_NE(table.find(s), nullptr) << lang << " " << s;
      EXPECT_TRUE(table.find(s)->closes_lips) << lang << " " << s;
      EXPECT_EQ(table.find(s)->viseme, 1);
    }
  }
}

TEST(PhonemeTable, VoiceForLanguage) {
  const LanguageTable pt = LanguageTable::for_language("pt");
  EXPECT_EQ(voice_for_language("pt", pt), "pt-br");
  EXPECT_EQ(voice_for_language("pt-pt", pt), "pt-pt");
  EXPECT_THROW(LanguageTable::for_language("fr"), InputError);
}

// Sixty seconds of real synthesised speech: frames cover the audio, and the last key lands
// within one frame of its phoneme.
TEST(Espeak, SixtySecondsStayInSync) {
  std::string text;
  const std::string base = sample_text("es");
  while (text.size() < 950) text += base;  // ~14 characters a second
  SpeechRequest request;
  request.text = text;
  request.language = "es";
  const PreparedSpeech prepared = prepare_speech(request, 0.3);
  ASSERT_GT(prepared.duration_s, 60.0);
  const auto& p = prepared.resolution.phonemes;
  const auto keys = plan_keys(p);
  const double fps = 25.0;
  const long n = frame_count_for(prepared.duration_s, fps);
  EXPECT_NEAR(static_cast<double>(n), prepared.duration_s * fps, 1.0);
  EXPECT_EQ(static_cast<long>(prepared.audio.samples.size()),
            std::lround(prepared.duration_s * prepared.audio.sample_rate));
  // The last non-neutral key sits on its phoneme (vowel centre or a boundary of its consonant).
  const Key* last = nullptr;
  for (const Key& k : keys)
    if (k.kind != KeyKind::Neutral) last = &k;
  ASSERT_NE(last, nullptr);
  const Phoneme& ph =
      p[static_cast<std::size_t>(last->kind == KeyKind::Vowel ? last->vowel : last->consonant)];
  EXPECT_GT(ph.start_s, 55.0);
  const double frame_time = std::round(last->time_s * fps) / fps;
  EXPECT_GE(frame_time, ph.start_s - 1.0 / fps);
  EXPECT_LE(frame_time, ph.end_s + 1.0 / fps);
}

}  // namespace
}  // namespace rostro::speech
