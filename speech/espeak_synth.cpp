#include "speech/espeak_synth.hpp"

#include <espeak-ng/speak_lib.h>

#include <cstdlib>
#include <cstring>
#include <mutex>
#include <stdexcept>

#include "facecore/error.hpp"

namespace rostro::speech {
namespace {

std::mutex g_espeak_mutex;
int g_sample_rate = 0;

struct Collector {
  Synthesis* out = nullptr;
};
Collector* g_collector = nullptr;  // guarded by g_espeak_mutex for the duration of a call

int on_synth(short* wav, int count, espeak_EVENT* events) {
  Synthesis& out = *g_collector->out;
  if (wav && count > 0) out.audio.samples.insert(out.audio.samples.end(), wav, wav + count);
  for (espeak_EVENT* ev = events; ev && ev->type != espeakEVENT_LIST_TERMINATED; ++ev) {
    if (ev->type != espeakEVENT_PHONEME) continue;
    char name[9] = {0};
    std::memcpy(name, ev->id.string, 8);
    RawPhoneme p;
    p.symbol = name;
    // `sample` is the exact sample index; audio_position (ms) is the same count rounded.
    p.start_s = static_cast<double>(ev->sample) / g_sample_rate;
    p.text_position = ev->text_position > 0 ? ev->text_position - 1 : -1;
    out.phonemes.push_back(std::move(p));
  }
  return 0;
}

void ensure_initialised() {
  if (g_sample_rate > 0) return;
  const int rate = espeak_Initialize(AUDIO_OUTPUT_SYNCHRONOUS, 0, nullptr,
                                     espeakINITIALIZE_PHONEME_EVENTS | espeakINITIALIZE_DONT_EXIT);
  if (rate <= 0)
    throw std::runtime_error("espeak-ng could not be initialised (is espeak-ng-data installed?)");
  g_sample_rate = rate;
  espeak_SetSynthCallback(on_synth);
}

// The name of an installed voice that speaks `language` ("en" also matches "en-us"), empty
// when none does. Each voice's `languages` is a list of (priority byte, name, NUL), ended by a
// zero priority byte.
std::string voice_speaking(const std::string& language) {
  for (const espeak_VOICE** v = espeak_ListVoices(nullptr); v && *v; ++v)
    for (const char* p = (*v)->languages; p && *p;) {
      const std::string name(p + 1);
      if (name == language || name.rfind(language + "-", 0) == 0) return (*v)->name;
      p += name.size() + 2;
    }
  return {};
}

// Language codes such as "pt-pt" or "en-gb" name no voice file: the voice that speaks the
// language is used, with the variant after '+' if one is given ("pt-pt+f3"). espeak-ng falls
// back to some voice for any code, so an unknown one is refused first.
bool set_voice_by_language(const std::string& code) {
  const auto plus = code.find('+');
  const std::string voice = voice_speaking(code.substr(0, plus));
  if (voice.empty()) return false;
  const std::string named = plus == std::string::npos ? voice : voice + code.substr(plus);
  return espeak_SetVoiceByName(named.c_str()) == EE_OK;
}

}  // namespace

constexpr int kDefaultPitch = 50;  // espeak-ng's own default

Synthesis synthesize(const std::string& text, const SynthOptions& options) {
  std::lock_guard lock(g_espeak_mutex);
  ensure_initialised();
  if (espeak_SetVoiceByName(options.voice.c_str()) != EE_OK &&
      !set_voice_by_language(options.voice))
    throw InputError("espeak-ng has no voice '" + options.voice +
                     "' (try es, es-419, pt, pt-br, en, en-us)");
  espeak_SetParameter(espeakRATE, options.rate_wpm > 0 ? options.rate_wpm : espeakRATE_NORMAL, 0);
  // espeak-ng's parameters are global: a pitch left by an earlier call must not carry over.
  espeak_SetParameter(espeakPITCH, options.pitch >= 0 ? options.pitch : kDefaultPitch, 0);

  Synthesis out;
  out.audio.sample_rate = g_sample_rate;
  Collector collector{&out};
  g_collector = &collector;
  const espeak_ERROR err = espeak_Synth(text.c_str(), text.size() + 1, 0, POS_CHARACTER, 0,
                                        espeakCHARS_UTF8, nullptr, nullptr);
  espeak_Synchronize();
  g_collector = nullptr;
  if (err != EE_OK) throw std::runtime_error("espeak-ng failed to synthesise the text");

  // Events mark starts; each phoneme ends where the next begins, the last at the audio end.
  const double end = out.audio.duration_s();
  for (std::size_t i = 0; i < out.phonemes.size(); ++i) {
    out.phonemes[i].end_s = i + 1 < out.phonemes.size() ? out.phonemes[i + 1].start_s : end;
    if (out.phonemes[i].end_s < out.phonemes[i].start_s)
      out.phonemes[i].end_s = out.phonemes[i].start_s;
  }
  return out;
}

}  // namespace rostro::speech
