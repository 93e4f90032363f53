// Rhubarb Lip Sync mouth cues (speech/mouth_cues): shapes, timing and each output format as
// Rhubarb's documentation specifies it.

#include "speech/mouth_cues.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <sstream>

#include "facecore/error.hpp"
#include "speech/espeak_synth.hpp"
#include "speech/phoneme_table.hpp"

namespace rostro::speech {
namespace {

const std::set<char> kShapes = {'A', 'B', 'C', 'D', 'E', 'F', 'G', 'H', 'X'};

std::vector<Phoneme> spoken(const std::string& text, const std::string& language,
                            double* duration) {
  SynthOptions o;
  o.voice = language;
  const Synthesis s = synthesize(text, o);
  *duration = s.audio.duration_s();
  return resolve(s.phonemes, LanguageTable::for_language(language)).phonemes;
}

Phoneme make(const std::string& symbol, PhonemeClass cls, int viseme) {
  Phoneme p;
  p.symbol = symbol;
  p.cls = cls;
  p.viseme = viseme;
  return p;
}

TEST(MouthCues, ShapesFollowTheVisemes) {
  EXPECT_EQ(mouth_shape(make("_", PhonemeClass::Silence, 0)), 'X');
  EXPECT_EQ(mouth_shape(make("m", PhonemeClass::Consonant, 1)), 'A');
  EXPECT_EQ(mouth_shape(make("f", PhonemeClass::Consonant, 2)), 'G');
  EXPECT_EQ(mouth_shape(make("l", PhonemeClass::Consonant, 8)), 'H');
  EXPECT_EQ(mouth_shape(make("n", PhonemeClass::Consonant, 8)), 'B');
  EXPECT_EQ(mouth_shape(make("a", PhonemeClass::Vowel, 10)), 'D');
  EXPECT_EQ(mouth_shape(make("e", PhonemeClass::Vowel, 11)), 'C');
  EXPECT_EQ(mouth_shape(make("i", PhonemeClass::Vowel, 12)), 'B');
  EXPECT_EQ(mouth_shape(make("o", PhonemeClass::Vowel, 13)), 'E');
  EXPECT_EQ(mouth_shape(make("u", PhonemeClass::Vowel, 14)), 'F');
}

TEST(MouthCues, CoverTheWholeClipWithRisingTimesAndEveryBilabialShown) {
  double duration = 0;
  const auto phonemes = spoken("Mamá, papá y Pablo beben batido de mango.", "es", &duration);
  const auto cues = mouth_cues(phonemes, duration);
  ASSERT_FALSE(cues.empty());
  EXPECT_DOUBLE_EQ(cues.front().start_s, 0.0);
  EXPECT_NEAR(cues.back().end_s, duration, 0.006);
  for (std::size_t k = 0; k < cues.size(); ++k) {
    EXPECT_TRUE(kShapes.count(cues[k].shape)) << cues[k].shape;
    EXPECT_GT(cues[k].end_s, cues[k].start_s);
    if (k > 0) {
      EXPECT_DOUBLE_EQ(cues[k].start_s, cues[k - 1].end_s);
      EXPECT_NE(cues[k].shape, cues[k - 1].shape);
    }
  }
  // m, p, p, b, b, b, m: each lies in (or touches) a closed-mouth cue.
  for (const Phoneme& p : phonemes) {
    if (!p.closes_lips) continue;
    const bool shown = std::any_of(cues.begin(), cues.end(), [&](const MouthCue& c) {
      return c.shape == 'A' && c.start_s <= p.end_s + 0.01 && c.end_s >= p.start_s - 0.01;
    });
    EXPECT_TRUE(shown) << p.symbol << " at " << p.start_s;
  }
}

TEST(MouthCues, EachFormatParsesAsRhubarbSpecifies) {
  double duration = 0;
  const auto phonemes = spoken("Hello, my name is Bob.", "en-us", &duration);
  const auto cues = mouth_cues(phonemes, duration);

  // TSV: "start<TAB>shape" per cue, the last line the end time with X; times rising.
  std::istringstream tsv(format_cues(cues, CueFormat::Tsv, "take.wav", duration));
  std::string line, last;
  double previous = -1;
  std::size_t lines = 0;
  while (std::getline(tsv, line)) {
    last = line;
    const auto tab = line.find('\t');
    ASSERT_NE(tab, std::string::npos) << line;
    const double t = std::stod(line.substr(0, tab));
    EXPECT_GT(t, previous);
    EXPECT_EQ(line.size(), tab + 2);
    EXPECT_TRUE(kShapes.count(line[tab + 1]));
    previous = t;
    ++lines;
  }
  EXPECT_EQ(lines, cues.size() + 1);
  EXPECT_EQ(last.back(), 'X');

  // JSON: metadata {soundFile, duration} and mouthCues [{start, end, value}].
  const auto json = nlohmann::json::parse(format_cues(cues, CueFormat::Json, "take.wav", duration));
  EXPECT_EQ(json["metadata"]["soundFile"], "take.wav");
  EXPECT_NEAR(json["metadata"]["duration"].get<double>(), duration, 0.006);
  ASSERT_EQ(json["mouthCues"].size(), cues.size());
  previous = -1;
  for (const auto& c : json["mouthCues"]) {
    EXPECT_GT(c["start"].get<double>(), previous);
    EXPECT_GT(c["end"].get<double>(), c["start"].get<double>());
    EXPECT_TRUE(kShapes.count(c["value"].get<std::string>().at(0)));
    previous = c["start"].get<double>();
  }

  // XML: <rhubarbResult><metadata>...</metadata><mouthCues><mouthCue start= end=>S</...>.
  const std::string xml = format_cues(cues, CueFormat::Xml, "a&b.wav", duration);
  EXPECT_EQ(xml.rfind("<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<rhubarbResult>", 0), 0u);
  EXPECT_NE(xml.find("<soundFile>a&amp;b.wav</soundFile>"), std::string::npos);
  const std::regex cue("<mouthCue start=\"([0-9.]+)\" end=\"([0-9.]+)\">([A-HX])</mouthCue>");
  EXPECT_EQ(static_cast<std::size_t>(std::distance(
                std::sregex_iterator(xml.begin(), xml.end(), cue), std::sregex_iterator())),
            cues.size());
  EXPECT_NE(xml.find("</mouthCues>\n</rhubarbResult>"), std::string::npos);

  // DAT (Moho switch data): a header, then "frame shape" with 1-based frames rising.
  std::istringstream dat(format_cues(cues, CueFormat::Dat, "take.wav", duration, 24.0));
  ASSERT_TRUE(std::getline(dat, line));
  EXPECT_EQ(line, "MohoSwitch1");
  long frame = 0;
  while (std::getline(dat, line)) {
    std::istringstream fields(line);
    long f = 0;
    std::string shape;
    ASSERT_TRUE(fields >> f >> shape) << line;
    EXPECT_GT(f, frame);
    EXPECT_TRUE(kShapes.count(shape.at(0)));
    frame = f;
  }
  EXPECT_NEAR(static_cast<double>(frame), 1 + duration * 24.0, 1.5);
}

TEST(MouthCues, FormatComesFromTheExtension) {
  EXPECT_EQ(cue_format_for("a.tsv"), CueFormat::Tsv);
  EXPECT_EQ(cue_format_for("a.json"), CueFormat::Json);
  EXPECT_EQ(cue_format_for("a.xml"), CueFormat::Xml);
  EXPECT_EQ(cue_format_for("a.dat"), CueFormat::Dat);
  EXPECT_THROW(cue_format_for("a.txt"), InputError);
}

}  // namespace
}  // namespace rostro::speech
