#include "render/sdl_audio_clock.hpp"

#include <SDL.h>
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "render/render_error.hpp"

namespace rostro::render {
namespace {

// ALSA writes its own lines to stderr while SDL probes for a device ("ALSA lib confmisc.c:855:
// cannot find card '0'", ...); SDL's error already says what matters, so stderr is quiet
// meanwhile (ROSTRO_AUDIO_LOG=1 keeps those lines).
class QuietStderr {
 public:
  QuietStderr() {
    if (std::getenv("ROSTRO_AUDIO_LOG") != nullptr) return;
    std::fflush(stderr);
    saved_ = dup(STDERR_FILENO);
    const int null = open("/dev/null", O_WRONLY);
    if (saved_ < 0 || null < 0 || dup2(null, STDERR_FILENO) < 0) restore();
    if (null >= 0) close(null);
  }
  ~QuietStderr() { restore(); }
  QuietStderr(const QuietStderr&) = delete;
  QuietStderr& operator=(const QuietStderr&) = delete;

 private:
  void restore() {
    if (saved_ < 0) return;
    std::fflush(stderr);
    dup2(saved_, STDERR_FILENO);
    close(saved_);
    saved_ = -1;
  }
  int saved_ = -1;
};

}  // namespace

struct SdlAudioClock::Impl {
  std::vector<std::int16_t> samples;
  int rate = 0;
  SDL_AudioDeviceID device = 0;
  SDL_AudioSpec have{};
  bool running = false;
  // Written by SDL's audio thread (next) or under SDL_LockAudioDevice (both).
  std::atomic<std::int64_t> next{0};    // the next sample the device takes
  std::atomic<std::int64_t> origin{0};  // where playback (re)started: start or seek

  static void fill(void* user, Uint8* stream, int bytes) {
    auto& m = *static_cast<Impl*>(user);
    auto* out = reinterpret_cast<std::int16_t*>(stream);
    const auto count = static_cast<std::int64_t>(bytes) / 2;
    const std::int64_t first = m.next.load();
    const auto size = static_cast<std::int64_t>(m.samples.size());
    const std::int64_t available = std::clamp<std::int64_t>(size - first, 0, count);
    if (available > 0)
      std::memcpy(out, m.samples.data() + first, static_cast<std::size_t>(available) * 2);
    std::fill(out + available, out + count, std::int16_t{0});  // silence after the end
    m.next.store(first + count);
  }
};

SdlAudioClock::SdlAudioClock(std::vector<std::int16_t> samples, int sample_rate)
    : impl_(std::make_unique<Impl>()) {
  if (sample_rate <= 0) throw std::invalid_argument("audio sample rate must be above 0");
  impl_->samples = std::move(samples);
  impl_->rate = sample_rate;
  QuietStderr quiet;
  if (SDL_InitSubSystem(SDL_INIT_AUDIO) != 0)
    throw RenderUnavailable(std::string("no audio (SDL: ") + SDL_GetError() + ")");
  SDL_AudioSpec want{};
  want.freq = sample_rate;
  want.format = AUDIO_S16SYS;
  want.channels = 1;
  want.samples = 1024;  // about 23 ms at 44.1 kHz: the clock's step
  want.callback = &Impl::fill;
  want.userdata = impl_.get();
  // No changes allowed: SDL converts to what the device wants, so samples stay ours.
  impl_->device = SDL_OpenAudioDevice(nullptr, 0, &want, &impl_->have, 0);
  if (impl_->device == 0) {
    const std::string why = SDL_GetError();
    SDL_QuitSubSystem(SDL_INIT_AUDIO);
    throw RenderUnavailable("no audio device (SDL: " + why + ")");
  }
}

SdlAudioClock::~SdlAudioClock() {
  SDL_CloseAudioDevice(impl_->device);
  SDL_QuitSubSystem(SDL_INIT_AUDIO);
}

void SdlAudioClock::start() {
  impl_->running = true;
  SDL_PauseAudioDevice(impl_->device, 0);
}

void SdlAudioClock::pause() {
  impl_->running = false;
  SDL_PauseAudioDevice(impl_->device, 1);
}

bool SdlAudioClock::paused() const {
  return !impl_->running;
}

std::int64_t SdlAudioClock::played_samples() const {
  // The device's buffer is taken before it is heard: the sample heard now is one buffer
  // behind the next one taken, but never before the point playback (re)started from.
  const std::int64_t heard = impl_->next.load() - static_cast<std::int64_t>(impl_->have.samples);
  return std::max(heard, impl_->origin.load());
}

std::int64_t SdlAudioClock::taken_samples() const {
  return impl_->next.load();
}

int SdlAudioClock::sample_rate() const {
  return impl_->rate;
}

double SdlAudioClock::position_s() const {
  return static_cast<double>(played_samples()) / impl_->rate;
}

void SdlAudioClock::seek(double seconds) {
  const auto sample = static_cast<std::int64_t>(std::llround(std::max(0.0, seconds) * impl_->rate));
  SDL_LockAudioDevice(impl_->device);
  impl_->next.store(sample);
  impl_->origin.store(sample);
  SDL_UnlockAudioDevice(impl_->device);
}

std::string SdlAudioClock::description() const {
  const char* driver = SDL_GetCurrentAudioDriver();
  return std::string(driver ? driver : "unknown driver") + ", " +
         std::to_string(impl_->have.samples) + "-sample buffer at " + std::to_string(impl_->rate) +
         " Hz";
}

}  // namespace rostro::render
