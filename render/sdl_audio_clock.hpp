#pragma once
// Sound for real-time playback, and the clock that playback follows: SDL2 audio plays mono
// 16-bit samples (then silence, for as long as the clock runs), and the clock's position is
// the count of samples the device has taken minus the device's buffer, i.e. the sample being
// heard now. It moves only as the device takes samples, so the picture follows the sound
// whatever the machine's load. SDL_AUDIODRIVER picks the driver (pulseaudio, alsa, ...;
// `dummy` and `disk` play nowhere, at the device's pace, for tests).

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "render/player.hpp"

namespace rostro::render {

class SdlAudioClock : public PlaybackClock {
 public:
  // Opens the default output device, paused. Throws RenderUnavailable, with SDL's reason,
  // when there is no audio device; std::invalid_argument for a sample rate <= 0.
  SdlAudioClock(std::vector<std::int16_t> samples, int sample_rate);
  ~SdlAudioClock() override;
  SdlAudioClock(const SdlAudioClock&) = delete;
  SdlAudioClock& operator=(const SdlAudioClock&) = delete;

  void start() override;
  void pause() override;
  bool paused() const override;
  double position_s() const override;
  void seek(double seconds) override;

  // The sample being heard now (position_s() x sample_rate()).
  std::int64_t played_samples() const;
  int sample_rate() const;
  // The samples the device has taken so far (played or in its buffer).
  std::int64_t taken_samples() const;
  // "pulseaudio, 1024-sample buffer at 44100 Hz"
  std::string description() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rostro::render
