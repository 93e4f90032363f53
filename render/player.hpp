#pragma once
// Real-time playback on a clock: the frame shown is the one the clock says is playing, picked
// anew every time the view is ready for a frame. With sound, the clock is the audio device's
// played position (render/sdl_audio_clock.hpp), so picture and sound cannot drift apart: a
// slow renderer skips frames, it never delays the sound. No window or audio here, so the
// loop is tested with a simulated clock and view (tests/render/player_test.cpp).

#include <chrono>
#include <cstdint>
#include <vector>

namespace rostro::render {

// The frame of a `fps` stream of `frame_count` frames that plays at `seconds`:
// floor(seconds x fps), clamped to 0..frame_count-1.
long frame_at(double seconds, double fps, long frame_count);
// The same at the `samples`-th sample of `sample_rate` audio: frame k starts at sample
// ceil(k x sample_rate / fps), exactly, for integer frame rates.
long frame_at_sample(std::int64_t samples, int sample_rate, double fps, long frame_count);

// Where playback is. Every call comes from the player's thread.
class PlaybackClock {
 public:
  virtual ~PlaybackClock() = default;
  virtual void start() = 0;  // starts or resumes from the current position
  virtual void pause() = 0;
  virtual bool paused() const = 0;
  virtual double position_s() const = 0;  // the time being played (heard) now
  virtual void seek(double seconds) = 0;
};

// The system's steady clock, for playback without sound.
class SteadyPlaybackClock : public PlaybackClock {
 public:
  void start() override;
  void pause() override;
  bool paused() const override { return !running_; }
  double position_s() const override;
  void seek(double seconds) override;

 private:
  using Clock = std::chrono::steady_clock;
  bool running_ = false;
  double base_s_ = 0;          // the position at started_
  Clock::time_point started_;  // when running_ became true
};

enum class PlayerCommand { TogglePause, SeekBack, SeekForward, Restart, Quit };

// Where frames go (a window) and where commands come from (its keys).
class PlayerView {
 public:
  virtual ~PlayerView() = default;
  // Shows frame `frame`, chosen at clock time `clock_s`; may take as long as it takes. After a
  // pause or a resume the frame at the clock is shown again (it may be the one shown).
  virtual void show(long frame, double clock_s) = 0;
  // The commands since the last call (window events are handled here).
  virtual std::vector<PlayerCommand> poll() = 0;
  // Nothing new to show yet: let a little time pass (a few milliseconds).
  virtual void wait() = 0;
};

struct PlayerOptions {
  double fps = 25;
  long frame_count = 0;
  double duration_s = 0;   // when playback ends; at least frame_count / fps (longer audio)
  double seek_step_s = 5;  // the arrows' jump
};

struct PlayerReport {
  long frames_shown = 0;
  long frames_skipped = 0;  // frames the clock passed while the view was busy
  double end_s = 0;         // the clock when playback ended
  bool quit = false;        // the user quit before the end
};

// Starts `clock` and shows frames until it reaches options.duration_s or the user quits.
// Throws std::invalid_argument for fps <= 0 or no frames.
PlayerReport play_on_clock(const PlayerOptions& options, PlaybackClock& clock, PlayerView& view);

}  // namespace rostro::render
