#include "render/player.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rostro::render {

long frame_at(double seconds, double fps, long frame_count) {
  if (frame_count <= 0) return 0;
  // The tolerance keeps a time exactly on a frame boundary (k / fps) on frame k.
  const double k = std::floor(seconds * fps + 1e-9);
  if (!(k > 0)) return 0;  // also NaN
  return k >= static_cast<double>(frame_count - 1) ? frame_count - 1 : static_cast<long>(k);
}

long frame_at_sample(std::int64_t samples, int sample_rate, double fps, long frame_count) {
  if (sample_rate <= 0) return 0;
  // samples x fps is exact in a double up to 2^53; one division rounds once.
  return frame_at(static_cast<double>(samples) * fps / sample_rate, 1.0, frame_count);
}

void SteadyPlaybackClock::start() {
  if (running_) return;
  started_ = Clock::now();
  running_ = true;
}

void SteadyPlaybackClock::pause() {
  base_s_ = position_s();
  running_ = false;
}

double SteadyPlaybackClock::position_s() const {
  if (!running_) return base_s_;
  return base_s_ + std::chrono::duration<double>(Clock::now() - started_).count();
}

void SteadyPlaybackClock::seek(double seconds) {
  base_s_ = seconds;
  started_ = Clock::now();
}

PlayerReport play_on_clock(const PlayerOptions& options, PlaybackClock& clock, PlayerView& view) {
  if (!(options.fps > 0)) throw std::invalid_argument("playback needs a frame rate above 0");
  if (options.frame_count <= 0) throw std::invalid_argument("playback needs at least one frame");
  const double duration =
      std::max(options.duration_s, static_cast<double>(options.frame_count) / options.fps);
  PlayerReport report;
  long last = -1;
  bool jumped = false;  // a seek: the next gap is not a skip
  bool redraw = false;  // paused or resumed: the view shows the frame again, in its new state
  clock.start();
  while (true) {
    for (const PlayerCommand command : view.poll()) {
      const double now = clock.position_s();
      switch (command) {
        case PlayerCommand::TogglePause:
          if (clock.paused())
            clock.start();
          else
            clock.pause();
          redraw = true;
          break;
        case PlayerCommand::SeekBack:
          clock.seek(std::max(0.0, now - options.seek_step_s));
          jumped = true;
          break;
        case PlayerCommand::SeekForward:
          clock.seek(std::min(duration, now + options.seek_step_s));
          jumped = true;
          break;
        case PlayerCommand::Restart:
          clock.seek(0);
          jumped = true;
          break;
        case PlayerCommand::Quit:
          report.quit = true;
          break;
      }
    }
    if (report.quit) break;
    const double t = clock.position_s();
    const long frame = frame_at(t, options.fps, options.frame_count);
    if (frame != last || redraw) {
      if (frame != last) {
        if (!jumped && last >= 0 && frame > last + 1) report.frames_skipped += frame - last - 1;
        ++report.frames_shown;
      }
      jumped = false;
      redraw = false;
      view.show(frame, t);
      last = frame;
      continue;
    }
    if (t >= duration && !clock.paused()) break;
    view.wait();
  }
  clock.pause();
  report.end_s = clock.position_s();
  return report;
}

}  // namespace rostro::render
