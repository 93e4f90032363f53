// The audio clock on a real SDL2 audio device: SDL's `disk` driver, which takes samples at a
// steady pace and writes them to a file (here, quickly: SDL_DISKAUDIODELAY 1 ms a buffer,
// about 20x real time). Frames shown follow the samples the device has taken, over 60 s of
// audio, and a slow renderer skips frames while the sound plays on.

#include "render/sdl_audio_clock.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <thread>
#include <vector>

#include "render/render_error.hpp"

namespace rostro::render {
namespace {

constexpr int kRate = 48000;
constexpr double kFps = 25;
constexpr long kFrames = 60 * 25;

struct Shown {
  long frame;
  double clock_s;
  std::int64_t taken;  // samples the device had taken when the frame was chosen
};

class RecordingView : public PlayerView {
 public:
  RecordingView(const SdlAudioClock& clock, std::chrono::milliseconds render)
      : clock_(clock), render_(render) {}
  void show(long frame, double clock_s) override {
    shown.push_back({frame, clock_s, clock_.taken_samples()});
    std::this_thread::sleep_for(render_);
  }
  std::vector<PlayerCommand> poll() override { return {}; }
  void wait() override { std::this_thread::sleep_for(std::chrono::microseconds(200)); }
  std::vector<Shown> shown;

 private:
  const SdlAudioClock& clock_;
  std::chrono::milliseconds render_;
};

class SdlAudioClockTest : public ::testing::Test {
 protected:
  void SetUp() override {
    setenv("SDL_AUDIODRIVER", "disk", 1);
    const auto file = std::filesystem::temp_directory_path() / "rostro-sdl-disk-audio.raw";
    setenv("SDL_DISKAUDIOFILE", file.c_str(), 1);
    setenv("SDL_DISKAUDIODELAY", "1", 1);
    std::vector<std::int16_t> samples(60 * kRate);
    for (std::size_t i = 0; i < samples.size(); ++i)
      samples[i] = static_cast<std::int16_t>((i / 50) % 2 ? 3000 : -3000);
    try {
      clock_ = std::make_unique<SdlAudioClock>(std::move(samples), kRate);
    } catch (const RenderUnavailable& e) {
      GTEST_SKIP() << "SDL's disk audio driver is not available here: " << e.what();
    }
  }
  void TearDown() override {
    clock_.reset();
    std::filesystem::remove(std::filesystem::temp_directory_path() / "rostro-sdl-disk-audio.raw");
  }
  PlayerOptions sixty_seconds() const {
    PlayerOptions o;
    o.fps = kFps;
    o.frame_count = kFrames;
    o.duration_s = 60;
    return o;
  }
  std::unique_ptr<SdlAudioClock> clock_;
};

TEST_F(SdlAudioClockTest, FramesFollowTheSamplesTheDeviceTookOverSixtySeconds) {
  RecordingView view(*clock_, std::chrono::milliseconds(0));
  const PlayerReport report = play_on_clock(sixty_seconds(), *clock_, view);
  ASSERT_FALSE(view.shown.empty());
  // The whole minute was heard, and the picture ended on the last frame with it.
  EXPECT_GE(clock_->played_samples(), 60 * kRate);
  EXPECT_GE(report.end_s, 60.0);
  EXPECT_EQ(view.shown.back().frame, kFrames - 1);
  for (std::size_t i = 0; i < view.shown.size(); ++i) {
    const Shown& s = view.shown[i];
    // The clock is the device's: the sample heard now is never one the device has not
    // taken yet.
    const auto heard = static_cast<std::int64_t>(std::llround(s.clock_s * kRate));
    EXPECT_LE(heard, s.taken);
    // No drift: the frame shown is the one whose audio is being heard.
    EXPECT_EQ(s.frame, frame_at_sample(heard, kRate, kFps, kFrames));
    if (i > 0) {
      EXPECT_GT(s.frame, view.shown[i - 1].frame);
    }
  }
}

TEST_F(SdlAudioClockTest, SlowRendererSkipsFramesWhileTheSoundPlaysOn) {
  // 30 ms a frame, while the device takes about 0.6 s of audio in that time.
  RecordingView view(*clock_, std::chrono::milliseconds(30));
  const PlayerReport report = play_on_clock(sixty_seconds(), *clock_, view);
  EXPECT_GE(clock_->played_samples(), 60 * kRate);
  EXPECT_GE(report.end_s, 60.0);
  EXPECT_LT(report.frames_shown, kFrames / 2);
  EXPECT_GT(report.frames_skipped, 0);
  EXPECT_EQ(view.shown.back().frame, kFrames - 1);
  for (const Shown& s : view.shown) EXPECT_EQ(s.frame, frame_at(s.clock_s, kFps, kFrames));
}

TEST_F(SdlAudioClockTest, PauseHoldsTheClockAndSeekMovesIt) {
  clock_->start();
  while (clock_->position_s() < 1.0) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  clock_->pause();
  const double held = clock_->position_s();
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_EQ(clock_->position_s(), held);
  EXPECT_TRUE(clock_->paused());
  clock_->seek(30.0);
  EXPECT_DOUBLE_EQ(clock_->position_s(), 30.0);
  clock_->start();
  while (clock_->position_s() < 31.0) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  EXPECT_GE(clock_->position_s(), 31.0);
  clock_->pause();
}

}  // namespace
}  // namespace rostro::render
