// MBROLA .pho parsing and the WAV writer/reader.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "facecore/error.hpp"
#include "speech/audio.hpp"
#include "speech/pho_reader.hpp"
#include "speech/pipeline.hpp"

namespace rostro::speech {
namespace {

std::filesystem::path temp_path(const std::string& name) {
  return std::filesystem::temp_directory_path() /
         ("rostro_speech_" + std::to_string(::getpid()) + "_" + name);
}

TEST(Pho, ParsesDurationsPitchAndComments) {
  std::istringstream in("; hola\n_ 100\no 80 0 120 50 130\nl 45.5\n\na 110 100 110 ; end\n_ 200\n");
  const auto p = parse_pho(in, "hola.pho");
  ASSERT_EQ(p.size(), 5u);
  EXPECT_EQ(p[1].symbol, "o");
  EXPECT_DOUBLE_EQ(p[1].start_s, 0.1);
  EXPECT_DOUBLE_EQ(p[2].end_s, 0.2255);
  EXPECT_DOUBLE_EQ(p[4].end_s, 0.5355);
  EXPECT_EQ(p[4].text_position, -1);
}

TEST(Pho, ErrorsNameFileAndLine) {
  const auto message = [](const std::string& text) {
    std::istringstream in(text);
    try {
      parse_pho(in, "x.pho");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("a 10\nb\n").find("x.pho:2"), std::string::npos);
  EXPECT_NE(message("a ten\n").find("x.pho:1: duration 'ten'"), std::string::npos);
  EXPECT_NE(message("a 10 50\n").find("pairs"), std::string::npos);
  EXPECT_NE(message("a -5\n").find("out of range"), std::string::npos);
  EXPECT_NE(message("; nothing\n").find("no phonemes"), std::string::npos);
}

TEST(Wav, WriteThenReadRoundTrips) {
  Audio a;
  a.sample_rate = 16000;
  for (int i = 0; i < 16000; ++i)
    a.samples.push_back(static_cast<std::int16_t>((i * 37) % 20000 - 10000));
  const auto path = temp_path("round.wav");
  write_wav(path, a);
  const Audio b = read_wav(path);
  EXPECT_EQ(b.sample_rate, 16000);
  EXPECT_EQ(b.samples, a.samples);
  EXPECT_DOUBLE_EQ(b.duration_s(), 1.0);
  std::filesystem::remove(path);
}

TEST(Wav, RejectsWhatIsNotAWav) {
  const auto path = temp_path("bad.wav");
  std::ofstream(path) << "this is not audio";
  EXPECT_THROW(read_wav(path), InputError);
  std::filesystem::remove(path);
  EXPECT_THROW(read_wav(temp_path("missing.wav")), InputError);
}

TEST(Pho, DrivesTheFaceWithAudioAsTheClock) {
  const auto pho = temp_path("drive.pho");
  const auto wav = temp_path("drive.wav");
  std::ofstream(pho) << "_ 150\np 60\na 140\nm 70\na 160\n_ 220\n";
  Audio a;
  a.sample_rate = 8000;
  a.samples.assign(8000 * 8 / 10, 0);  // 0.8 s, the same as the .pho
  write_wav(wav, a);
  SpeechRequest r;
  r.language = "es";
  r.pho = pho;
  r.audio = wav;
  const PreparedSpeech p = prepare_speech(r, 0.3);
  EXPECT_TRUE(p.warnings.empty());
  EXPECT_DOUBLE_EQ(p.duration_s, 0.8);
  EXPECT_EQ(p.resolution.phonemes.size(), 6u);
  a.samples.resize(8000);  // 1.0 s: a mismatch is reported, the audio length wins
  write_wav(wav, a);
  const PreparedSpeech q = prepare_speech(r, 0.3);
  ASSERT_EQ(q.warnings.size(), 1u);
  EXPECT_DOUBLE_EQ(q.duration_s, 1.0);
  std::filesystem::remove(pho);
  std::filesystem::remove(wav);
}

}  // namespace
}  // namespace rostro::speech
