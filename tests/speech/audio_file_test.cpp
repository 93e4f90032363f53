// Recordings in through FFmpeg (speech/audio_file): formats, rates, channels, bad files.

#include "speech/audio_file.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "facecore/error.hpp"
#include "speech/audio.hpp"

namespace rostro::speech {
namespace {

std::filesystem::path scratch() {
  const auto dir =
      std::filesystem::temp_directory_path() / ("rostro_audio_file_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return dir;
}

// One second of a 440 Hz tone at 22050 Hz.
Audio tone() {
  Audio a;
  a.sample_rate = 22050;
  for (int i = 0; i < 22050; ++i)
    a.samples.push_back(static_cast<std::int16_t>(8000 * std::sin(2 * M_PI * 440 * i / 22050.0)));
  return a;
}

double rms(const Audio& a) {
  double sum = 0;
  for (auto s : a.samples) sum += static_cast<double>(s) * s;
  return std::sqrt(sum / static_cast<double>(a.samples.size()));
}

bool ffmpeg(const std::string& args) {
  return std::system(("ffmpeg -loglevel error -y " + args).c_str()) == 0;
}

TEST(AudioFile, ReadsEveryCommonFormatAtItsOwnRate) {
  const auto dir = scratch();
  const auto wav = dir / "tone.wav";
  write_wav(wav, tone());
  const Audio direct = read_audio(wav);
  EXPECT_EQ(direct.sample_rate, 22050);
  EXPECT_EQ(direct.samples, tone().samples);
  for (const std::string ext : {"flac", "mp3", "ogg", "m4a"}) {
    const auto out = dir / ("tone." + ext);
    ASSERT_TRUE(ffmpeg("-i " + wav.string() + " " + out.string())) << ext;
    const Audio a = read_audio(out);
    EXPECT_EQ(a.sample_rate, 22050) << ext;
    // Lossy codecs pad the start and end a little; the length stays within 0.1 s.
    EXPECT_NEAR(a.duration_s(), 1.0, 0.1) << ext;
    EXPECT_NEAR(rms(a), rms(tone()), 0.1 * rms(tone())) << ext;
  }
  std::filesystem::remove_all(dir);
}

TEST(AudioFile, StereoIsMixedToMonoAndResamplingKeepsTheLength) {
  const auto dir = scratch();
  const auto stereo = dir / "stereo.wav";
  ASSERT_TRUE(ffmpeg("-f lavfi -i sine=frequency=300:sample_rate=48000:duration=2 -ac 2 " +
                     stereo.string()));
  const Audio a = read_audio(stereo);
  EXPECT_EQ(a.sample_rate, 48000);
  EXPECT_NEAR(a.duration_s(), 2.0, 0.01);
  const Audio b = resample(a, 16000);
  EXPECT_EQ(b.sample_rate, 16000);
  EXPECT_NEAR(b.duration_s(), 2.0, 0.01);
  EXPECT_NEAR(rms(b), rms(a), 0.05 * rms(a));
  std::filesystem::remove_all(dir);
}

TEST(AudioFile, BadFilesAreOneClearError) {
  const auto dir = scratch();
  const auto message = [](const std::filesystem::path& p) {
    try {
      read_audio(p);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  std::ofstream(dir / "text.mp3") << "this is not audio\n";
  std::ofstream(dir / "empty.wav");
  EXPECT_NE(message(dir / "text.mp3").find("text.mp3: not a recording"), std::string::npos);
  EXPECT_NE(message(dir / "empty.wav").find("empty.wav: "), std::string::npos);
  EXPECT_NE(message(dir / "absent.flac").find("no such audio file"), std::string::npos);
  // A video without sound.
  ASSERT_TRUE(ffmpeg("-f lavfi -i testsrc=size=64x48:duration=0.2 " + (dir / "mute.mp4").string()));
  EXPECT_NE(message(dir / "mute.mp4").find("has no audio stream"), std::string::npos);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace rostro::speech
