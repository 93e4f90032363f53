// Playback on a clock: frames follow the clock, a slow renderer skips frames instead of
// stretching time, and the keys pause and seek. The clock here is simulated: it moves only
// while the view renders or waits, as a sound device plays on while a renderer works.

#include "render/player.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <utility>
#include <vector>

namespace rostro::render {
namespace {

class SimulatedClock : public PlaybackClock {
 public:
  void start() override { running_ = true; }
  void pause() override { running_ = false; }
  bool paused() const override { return !running_; }
  double position_s() const override { return t_; }
  void seek(double seconds) override { t_ = seconds; }
  void advance(double seconds) {
    if (running_) t_ += seconds;
  }

 private:
  bool running_ = false;
  double t_ = 0;
};

struct Shown {
  long frame;
  double clock_s;
};

class RecordingView : public PlayerView {
 public:
  RecordingView(SimulatedClock& clock, double render_s) : clock_(clock), render_s_(render_s) {}
  void show(long frame, double clock_s) override {
    shown.push_back({frame, clock_s});
    clock_.advance(render_s_);
  }
  std::vector<PlayerCommand> poll() override {
    ++polls;
    return script ? script(*this) : std::vector<PlayerCommand>{};
  }
  void wait() override { clock_.advance(0.002); }

  std::vector<Shown> shown;
  long polls = 0;
  std::function<std::vector<PlayerCommand>(RecordingView&)> script;

 private:
  SimulatedClock& clock_;
  double render_s_;
};

constexpr double kFps = 25;
constexpr long kFrames = 60 * 25;  // 60 s

PlayerOptions sixty_seconds() {
  PlayerOptions o;
  o.fps = kFps;
  o.frame_count = kFrames;
  o.duration_s = 60;
  return o;
}

TEST(FrameAt, FrameKStartsAtItsSampleExactly) {
  for (long k = 0; k < 2000; ++k) {
    const std::int64_t first = k * 1920;  // 48 kHz at 25 fps
    EXPECT_EQ(frame_at_sample(first, 48000, 25, 100000), k);
    if (k > 0) {
      EXPECT_EQ(frame_at_sample(first - 1, 48000, 25, 100000), k - 1);
    }
  }
  // 44.1 kHz at 30 fps: 1470 samples a frame.
  EXPECT_EQ(frame_at_sample(1469, 44100, 30, 10), 0);
  EXPECT_EQ(frame_at_sample(1470, 44100, 30, 10), 1);
  // Before the start and past the end the first and last frames show.
  EXPECT_EQ(frame_at(-1.0, 25, 10), 0);
  EXPECT_EQ(frame_at(100.0, 25, 10), 9);
  EXPECT_EQ(frame_at(std::nan(""), 25, 10), 0);
}

TEST(Player, FastViewShowsEveryFrameOnTheClockOverSixtySeconds) {
  SimulatedClock clock;
  RecordingView view(clock, 0.001);
  const PlayerReport report = play_on_clock(sixty_seconds(), clock, view);
  ASSERT_EQ(report.frames_shown, kFrames);
  EXPECT_EQ(report.frames_skipped, 0);
  EXPECT_FALSE(report.quit);
  for (std::size_t i = 0; i < view.shown.size(); ++i) {
    EXPECT_EQ(view.shown[i].frame, static_cast<long>(i));
    // No drift: the frame shown is the one playing when it was chosen.
    EXPECT_EQ(view.shown[i].frame, frame_at(view.shown[i].clock_s, kFps, kFrames));
    EXPECT_LT(view.shown[i].clock_s - static_cast<double>(i) / kFps, 1.0 / kFps);
  }
  EXPECT_GE(report.end_s, 60.0);
  EXPECT_LT(report.end_s, 60.01);
}

TEST(Player, SlowRendererSkipsFramesInsteadOfStretchingTime) {
  SimulatedClock clock;
  RecordingView view(clock, 0.1);  // 2.5 frame periods a frame
  const PlayerReport report = play_on_clock(sixty_seconds(), clock, view);
  // A renderer that waited for every frame would end at 1500 x 0.1 s = 150 s.
  EXPECT_GE(report.end_s, 60.0);
  EXPECT_LT(report.end_s, 60.2);
  EXPECT_LT(report.frames_shown, kFrames / 2);
  EXPECT_GT(report.frames_skipped, kFrames / 2);
  EXPECT_EQ(report.frames_shown + report.frames_skipped, kFrames);
  EXPECT_EQ(view.shown.back().frame, kFrames - 1);
  for (std::size_t i = 0; i < view.shown.size(); ++i) {
    EXPECT_EQ(view.shown[i].frame, frame_at(view.shown[i].clock_s, kFps, kFrames));
    if (i > 0) {
      EXPECT_GT(view.shown[i].frame, view.shown[i - 1].frame);
    }
  }
}

TEST(Player, AudioLongerThanTheFramesHoldsTheLastFrameUntilTheSoundEnds) {
  SimulatedClock clock;
  RecordingView view(clock, 0.001);
  PlayerOptions o = sixty_seconds();
  o.duration_s = 63;
  const PlayerReport report = play_on_clock(o, clock, view);
  EXPECT_EQ(report.frames_shown, kFrames);
  EXPECT_GE(report.end_s, 63.0);
}

TEST(Player, SpacePausesTheClockAndArrowsSeek) {
  SimulatedClock clock;
  RecordingView view(clock, 0.001);
  int step = 0;
  double paused_at = -1;
  long shown_while_paused = -1;
  view.script = [&](RecordingView& v) -> std::vector<PlayerCommand> {
    const double t = clock.position_s();
    if (step == 0 && t >= 10) {
      ++step;
      paused_at = t;
      return {PlayerCommand::TogglePause};
    }
    if (step == 1 && shown_while_paused < 0)  // the frame at the paused time is shown
      shown_while_paused = static_cast<long>(v.shown.size());
    if (step == 1 && v.polls > 20000) {  // a while later, still at the same time
      EXPECT_EQ(clock.position_s(), paused_at);
      EXPECT_EQ(static_cast<long>(v.shown.size()), shown_while_paused);
      ++step;
      return {PlayerCommand::TogglePause, PlayerCommand::SeekForward};
    }
    if (step == 2 && t >= 30) {
      ++step;
      return {PlayerCommand::SeekBack, PlayerCommand::SeekBack};
    }
    if (step == 3 && t >= 40) {
      ++step;
      return {PlayerCommand::Quit};
    }
    return {};
  };
  const PlayerReport report = play_on_clock(sixty_seconds(), clock, view);
  EXPECT_TRUE(report.quit);
  EXPECT_EQ(step, 4);
  EXPECT_GE(report.end_s, 40.0);
  EXPECT_LT(report.end_s, 41.0);
  // After the forward seek the next frame shown is 5 s (125 frames) on; after the two
  // back seeks, 10 s back; seeks are not counted as skipped frames.
  bool forward = false, back = false;
  for (std::size_t i = 1; i < view.shown.size(); ++i) {
    const long jump = view.shown[i].frame - view.shown[i - 1].frame;
    forward |= jump >= 125 && jump <= 126;
    back |= jump <= -249 && jump >= -250;
  }
  EXPECT_TRUE(forward);
  EXPECT_TRUE(back);
  EXPECT_EQ(report.frames_skipped, 0);
}

TEST(Player, RejectsNoFramesAndNoFrameRate) {
  SimulatedClock clock;
  RecordingView view(clock, 0.001);
  PlayerOptions o = sixty_seconds();
  o.frame_count = 0;
  EXPECT_THROW(play_on_clock(o, clock, view), std::invalid_argument);
  o = sixty_seconds();
  o.fps = 0;
  EXPECT_THROW(play_on_clock(o, clock, view), std::invalid_argument);
}

}  // namespace
}  // namespace rostro::render
