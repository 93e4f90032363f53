// Forced alignment of a recording to its transcript (speech/forced_align), and phone
// recognition without one (speech/phone_recognizer): against recordings whose phoneme times
// are known and which the alignment's reference did not make, and against real voices.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>

#include "facecore/error.hpp"
#include "facecore/expression_library.hpp"
#include "speech/animator.hpp"
#include "speech/audio_file.hpp"
#include "speech/espeak_synth.hpp"
#include "speech/forced_align.hpp"
#include "speech/phone_recognizer.hpp"
#include "speech/phoneme_table.hpp"
#include "speech/speech_presence.hpp"

namespace rostro::speech {
namespace {

const char* const kSpanish =
    "Cuando por fin llegamos a Madrid, el sol brillaba sobre los tejados y la ciudad olía a pan "
    "recién hecho. Mi abuela nos esperaba en la puerta con un plato de membrillo.";
const char* const kEnglish =
    "A man beside me was reading a map of the mountains, and his daughter made a paper boat "
    "from an old newspaper.";

// Real recordings of a human voice (Debian's alsa-utils): "Front left" and others.
const std::filesystem::path kAlsaSounds = "/usr/share/sounds/alsa";

Synthesis say(const std::string& text, const std::string& voice, int rate, int pitch = -1) {
  SynthOptions o;
  o.voice = voice;
  o.rate_wpm = rate;
  o.pitch = pitch;
  return synthesize(text, o);
}

AlignmentOptions reference(const std::string& voice) {
  AlignmentOptions o;
  o.reference.voice = voice;
  return o;
}

// |aligned start - true start| in ms for every phoneme that is not a pause: the two
// sequences say the same phonemes (the alignment adds and merges pauses of its own).
std::vector<double> boundary_errors_ms(const std::vector<RawPhoneme>& aligned,
                                       const std::vector<RawPhoneme>& truth) {
  auto spoken = [](const std::vector<RawPhoneme>& all) {
    std::vector<RawPhoneme> out;
    for (const RawPhoneme& p : all)
      if (p.symbol[0] != '_') out.push_back(p);
    return out;
  };
  const auto a = spoken(aligned), t = spoken(truth);
  EXPECT_EQ(a.size(), t.size());
  std::vector<double> errors;
  for (std::size_t k = 0; k < std::min(a.size(), t.size()); ++k) {
    EXPECT_EQ(a[k].symbol, t[k].symbol);
    errors.push_back(1000.0 * std::abs(a[k].start_s - t[k].start_s));
  }
  return errors;
}

double quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1))];
}

void add_noise(Audio& audio, double snr_db) {
  double power = 0;
  for (auto s : audio.samples) power += static_cast<double>(s) * s;
  const double sigma =
      std::sqrt(power / static_cast<double>(audio.samples.size()) / std::pow(10.0, snr_db / 10));
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, sigma);
  for (auto& s : audio.samples)
    s = static_cast<std::int16_t>(std::clamp(s + noise(rng), -32768.0, 32767.0));
}

void expect_contiguous(const std::vector<RawPhoneme>& p, double end) {
  ASSERT_FALSE(p.empty());
  EXPECT_DOUBLE_EQ(p.front().start_s, 0.0);
  for (std::size_t k = 1; k < p.size(); ++k) EXPECT_DOUBLE_EQ(p[k].start_s, p[k - 1].end_s);
  EXPECT_DOUBLE_EQ(p.back().end_s, end);
}

TEST(ForcedAlignment, AnotherVoiceAndRateWithin20msMedian50msP95) {
  const Synthesis recording = say(kSpanish, "es+f3", 135, 70);
  const Alignment a = align_transcript(recording.audio, kSpanish, reference("es"));
  expect_contiguous(a.phonemes, recording.audio.duration_s());
  const auto errors = boundary_errors_ms(a.phonemes, recording.phonemes);
  EXPECT_LE(quantile(errors, 0.5), 20.0);
  EXPECT_LE(quantile(errors, 0.95), 50.0);
  EXPECT_LT(a.match_ratio, 0.9);
}

TEST(ForcedAlignment, NoisyResampledRecordingStillAligns) {
  Synthesis recording = say(kEnglish, "en-us+m3", 200);
  recording.audio = resample(recording.audio, 44100);
  add_noise(recording.audio, 15.0);
  const Alignment a = align_transcript(recording.audio, kEnglish, reference("en-us"));
  const auto errors = boundary_errors_ms(a.phonemes, recording.phonemes);
  EXPECT_LE(quantile(errors, 0.5), 20.0);
  EXPECT_LE(quantile(errors, 0.95), 50.0);
}

TEST(ForcedAlignment, NoDriftOverAMinute) {
  std::string text;
  for (int k = 0; k < 6; ++k) text += std::string(k ? " " : "") + kSpanish;
  const Synthesis recording = say(text, "es+m2", 150);
  ASSERT_GT(recording.audio.duration_s(), 55.0);
  const Alignment a = align_transcript(recording.audio, text, reference("es"));
  std::vector<RawPhoneme> truth;
  for (const RawPhoneme& p : recording.phonemes)
    if (p.symbol[0] != '_') truth.push_back(p);
  const std::vector<double> errors = boundary_errors_ms(a.phonemes, recording.phonemes);
  ASSERT_EQ(errors.size(), truth.size());
  std::vector<double> early, late;
  for (std::size_t k = 0; k < truth.size(); ++k) {
    if (truth[k].start_s < 10.0) early.push_back(errors[k]);
    if (truth[k].start_s > recording.audio.duration_s() - 10.0) late.push_back(errors[k]);
  }
  EXPECT_LE(quantile(late, 0.5), 20.0);
  EXPECT_LE(quantile(late, 0.95), 50.0);
  EXPECT_LE(quantile(late, 0.5), quantile(early, 0.5) + 10.0);
}

TEST(ForcedAlignment, EveryBilabialClosesTheLipsWithinAFrame) {
  const Synthesis recording = say(kSpanish, "es+f2", 160, 60);
  const Alignment a = align_transcript(recording.audio, kSpanish, reference("es"));
  const LanguageTable table = LanguageTable::for_language("es");
  const ExpressionLibrary library = ExpressionLibrary::load_default();
  const KeyShapes shapes = KeyShapes::load_default(library);
  AnimationOptions o;
  o.blinks = o.saccades = o.head_motion = false;
  const Animator animator(resolve(a.phonemes, table).phonemes, recording.audio.duration_s(), {},
                          library, shapes, BehaviourSettings::load_default(), o);
  int bilabials = 0;
  for (const Phoneme& p : resolve(recording.phonemes, table).phonemes) {
    if (!p.closes_lips) continue;
    ++bilabials;
    double nearest = 1e9;
    for (long k = 0; k < animator.frame_count(); ++k)
      if (shapes.lips_closed(animator.frame(k).values)) {
        const double t = static_cast<double>(k) / o.fps;
        nearest = std::min(nearest, std::max({0.0, p.start_s - t, t - p.end_s}));
      }
    EXPECT_LE(nearest * o.fps, 1.0) << p.symbol << " at " << p.start_s;
  }
  EXPECT_GE(bilabials, 5);
}

TEST(ForcedAlignment, AnotherLanguageStandsOut) {
  // A Spanish reading checked against an English transcript: far above the right
  // transcript's ratio (both vary by a few hundredths from run to run: espeak-ng's
  // synthesis is not bit-identical from call to call).
  const Synthesis recording = say(kSpanish, "es+f3", 150);
  AlignmentOptions english = reference("en-us");
  english.max_match_ratio = 10.0;
  const double wrong = align_transcript(recording.audio, kEnglish, english).match_ratio;
  const double right = align_transcript(recording.audio, kSpanish, reference("es")).match_ratio;
  EXPECT_GT(wrong, 0.75);
  EXPECT_GT(wrong, right + 0.3);
}

// A transcript that leaves a line out: the recording's speech there is reported, and a
// complete transcript reports none.
TEST(ForcedAlignment, SpeechTheTranscriptLeavesOutIsReported) {
  const std::string extra = " Después fuimos al mercado a comprar fruta.";
  const Synthesis recording = say(std::string(kSpanish) + extra, "es+f3", 150);
  // Where the extra sentence starts: its first phoneme (text positions count code points).
  const std::string first(kSpanish);
  const auto code_points =
      std::count_if(first.begin(), first.end(), [](char c) { return (c & 0xC0) != 0x80; });
  double extra_start = 0.0;
  for (const RawPhoneme& p : recording.phonemes)
    if (p.text_position >= code_points) {
      extra_start = p.start_s;
      break;
    }
  ASSERT_GT(extra_start, 5.0);
  const Alignment short_text = align_transcript(recording.audio, kSpanish, reference("es"));
  ASSERT_EQ(short_text.uncovered_speech.size(), 1u);
  // The neighbouring word stretches over part of the missing one: the span starts within
  // half a second of it.
  EXPECT_NEAR(short_text.uncovered_speech[0].first, extra_start, 0.5);
  EXPECT_GT(short_text.uncovered_speech[0].second - short_text.uncovered_speech[0].first, 1.0);
  const Alignment whole =
      align_transcript(recording.audio, std::string(kSpanish) + extra, reference("es"));
  EXPECT_TRUE(whole.uncovered_speech.empty());
}

TEST(ForcedAlignment, RealVoicesPass) {
  if (!std::filesystem::exists(kAlsaSounds / "Front_Left.wav"))
    GTEST_SKIP() << kAlsaSounds << " is absent (Debian package alsa-utils)";
  for (const auto& [file, text] :
       std::vector<std::pair<std::string, std::string>>{{"Front_Left.wav", "Front left"},
                                                        {"Rear_Right.wav", "Rear right"},
                                                        {"Side_Right.wav", "Side right"}}) {
    // Half a second of room noise before the voice: the words start where the voice does.
    Audio voice = read_audio(kAlsaSounds / file);
    Audio padded = voice;
    padded.samples.assign(static_cast<std::size_t>(voice.sample_rate / 2), 0);
    std::mt19937 rng(1);
    std::normal_distribution<double> hiss(0.0, 30.0);
    for (auto& s : padded.samples) s = static_cast<std::int16_t>(hiss(rng));
    padded.samples.insert(padded.samples.end(), voice.samples.begin(), voice.samples.end());
    const Alignment a = align_transcript(padded, text, reference("en-us"));
    EXPECT_LT(a.match_ratio, reference("en-us").max_match_ratio) << file;
    EXPECT_TRUE(a.uncovered_speech.empty())
        << file << " " << (a.uncovered_speech.empty() ? 0 : a.uncovered_speech[0].first) << "-"
        << (a.uncovered_speech.empty() ? 0 : a.uncovered_speech[0].second) << " voice "
        << a.reference_voice;
    const auto first = std::find_if(a.phonemes.begin(), a.phonemes.end(),
                                    [](const RawPhoneme& p) { return p.symbol[0] != '_'; });
    ASSERT_NE(first, a.phonemes.end());
    // The voice's onset: its first sample above a tenth of its peak.
    int peak = 0;
    for (auto v : voice.samples) peak = std::max(peak, std::abs(static_cast<int>(v)));
    const auto onset = std::find_if(voice.samples.begin(), voice.samples.end(),
                                    [&](std::int16_t v) { return std::abs(v) * 10 > peak; });
    const double onset_s = static_cast<double>(onset - voice.samples.begin()) / voice.sample_rate;
    // (An f fading in from room noise moves its start by about 0.1 s either way.)
    EXPECT_NEAR(first->start_s, 0.5 + onset_s, 0.15) << file;
  }
}

TEST(SpeechPresence, VoicesPassNoiseTonesAndSilenceDoNot) {
  const auto refused = [](const Audio& a) {
    try {
      require_speech(a, "take.wav");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  for (const char* voice : {"es", "en-us+f3", "pt+m2"}) {
    Synthesis s = say(kSpanish, voice, 0);
    EXPECT_EQ(refused(s.audio), "") << voice;
    add_noise(s.audio, 10.0);
    EXPECT_EQ(refused(s.audio), "") << voice << " under noise";
  }
  Audio silence;
  silence.sample_rate = 16000;
  silence.samples.assign(32000, 0);
  EXPECT_NE(refused(silence).find("take.wav: silent"), std::string::npos);
  Audio hiss = silence;
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> white(-8000, 8000);
  for (auto& s : hiss.samples) s = static_cast<std::int16_t>(white(rng));
  EXPECT_NE(refused(hiss).find("no speech found"), std::string::npos);
  Audio chord = silence;
  for (std::size_t i = 0; i < chord.samples.size(); ++i)
    chord.samples[i] = static_cast<std::int16_t>(
        4000 * (std::sin(2 * M_PI * 440 * static_cast<double>(i) / 16000.0) +
                std::sin(2 * M_PI * 660 * static_cast<double>(i) / 16000.0)));
  EXPECT_NE(refused(chord).find("no speech found"), std::string::npos);
  if (!std::filesystem::exists(kAlsaSounds / "Noise.wav"))
    GTEST_SKIP() << kAlsaSounds << " is absent (Debian package alsa-utils)";
  EXPECT_NE(refused(read_audio(kAlsaSounds / "Noise.wav")).find("no speech found"),
            std::string::npos);
  for (const char* file : {"Front_Left.wav", "Rear_Right.wav", "Side_Right.wav"})
    EXPECT_EQ(refused(read_audio(kAlsaSounds / file)), "") << file;
}

TEST(PhoneRecognition, ArpabetNamesMapToTheEnglishTable) {
  const LanguageTable table = LanguageTable::for_language("en");
  for (const char* phone :
       {"AA", "AE", "AH", "AO", "AW", "AY", "B", "CH", "D", "DH", "EH", "ER", "EY", "F",
        "G",  "HH", "IH", "IY", "JH", "K",  "L", "M",  "N", "NG", "OW", "OY", "P",  "R",
        "S",  "SH", "T",  "TH", "UH", "UW", "V", "W",  "Y", "Z",  "ZH", "SIL"}) {
    const std::string symbol = espeak_symbol_for_arpabet(phone);
    ASSERT_FALSE(symbol.empty()) << phone;
    EXPECT_NE(table.find(symbol), nullptr) << phone << " -> " << symbol;
  }
  EXPECT_EQ(espeak_symbol_for_arpabet("+NSN+"), "_");
  EXPECT_EQ(espeak_symbol_for_arpabet("QQ"), "");
}

// How well PocketSphinx finds phones is measured by `rostro eval alignment` (and checked in
// tests/eval); here, that a real voice gives a timeline with speech where the voice is.
TEST(PhoneRecognition, ARealVoiceGivesSpeechWhereTheVoiceIs) {
  if (!std::filesystem::exists(kAlsaSounds / "Rear_Left.wav"))
    GTEST_SKIP() << kAlsaSounds << " is absent (Debian package alsa-utils)";
  const Audio voice = read_audio(kAlsaSounds / "Rear_Left.wav");
  Audio padded = voice;
  padded.samples.assign(static_cast<std::size_t>(voice.sample_rate), 0);
  padded.samples.insert(padded.samples.end(), voice.samples.begin(), voice.samples.end());
  const auto phones = recognize_phones(padded);
  expect_contiguous(phones, padded.duration_s());
  const LanguageTable table = LanguageTable::for_language("en");
  double speech_s = 0.0;
  for (const RawPhoneme& p : phones) {
    const PhonemeInfo* info = table.find(p.symbol);
    ASSERT_NE(info, nullptr) << p.symbol;
    if (info->cls == PhonemeClass::Silence) continue;
    EXPECT_GE(p.start_s, 0.95) << p.symbol << " before the voice starts";
    speech_s += p.end_s - p.start_s;
  }
  EXPECT_GT(speech_s, 0.5 * voice.duration_s());
}

}  // namespace
}  // namespace rostro::speech
