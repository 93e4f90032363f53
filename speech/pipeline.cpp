#include "speech/pipeline.hpp"

#include <fmt/format.h>

#include <cmath>

#include "facecore/error.hpp"
#include "speech/espeak_synth.hpp"
#include "speech/pho_reader.hpp"

namespace rostro::speech {

std::string voice_for_language(const std::string& language, const LanguageTable& table) {
  if (language.find_first_of("-_") != std::string::npos) return language;
  return table.default_voice();
}

double tag_time(std::size_t position, const std::vector<RawPhoneme>& raw,
                const LanguageTable& table) {
  double t = 0.0;
  for (const RawPhoneme& p : raw) {
    const PhonemeInfo* info = table.find(p.symbol);
    if (info && info->cls == PhonemeClass::Silence && !info->modifier) continue;
    if (p.text_position < 0 || static_cast<std::size_t>(p.text_position) >= position) continue;
    t = std::max(t, p.end_s);
  }
  return t;
}

PreparedSpeech prepare_speech(const SpeechRequest& request, double default_ramp_s) {
  const LanguageTable table = LanguageTable::for_language(request.language);
  PreparedSpeech out;
  if (!request.pho.empty()) {
    out.raw = read_pho(request.pho);
    const double pho_end = out.raw.back().end_s;
    if (!request.audio.empty()) {
      out.audio = read_wav(request.audio);
      out.duration_s = out.audio.duration_s();
      if (std::abs(pho_end - out.duration_s) > 0.04)
        out.warnings.push_back(
            fmt::format("{} lasts {:.3f} s but {} lasts {:.3f} s; frames follow the audio",
                        request.pho.string(), pho_end, request.audio.string(), out.duration_s));
    } else {
      out.duration_s = pho_end;
    }
    if (!request.text.empty()) {
      // Markup with a .pho has no words to anchor to: tags must stand at the start.
      const MarkedText marked = parse_emotion_markup(request.text, "emotion text");
      for (const EmotionTag& tag : marked.tags)
        out.emotions.push_back(
            {0.0, tag.expression, tag.intensity, tag.ramp_s >= 0 ? tag.ramp_s : default_ramp_s});
    }
  } else {
    const MarkedText marked = parse_emotion_markup(request.text);
    bool has_letters = false;
    for (char c : marked.clean) has_letters |= !std::isspace(static_cast<unsigned char>(c));
    if (!has_letters)
      throw InputError("nothing to say: the text is empty once emotion tags are removed");
    SynthOptions synth;
    synth.voice =
        request.voice.empty() ? voice_for_language(request.language, table) : request.voice;
    synth.rate_wpm = request.rate_wpm;
    Synthesis s = synthesize(marked.clean, synth);
    out.voice = synth.voice;
    out.audio = std::move(s.audio);
    out.duration_s = out.audio.duration_s();
    out.raw = std::move(s.phonemes);
    for (const EmotionTag& tag : marked.tags)
      out.emotions.push_back({tag_time(tag.position, out.raw, table), tag.expression, tag.intensity,
                              tag.ramp_s >= 0 ? tag.ramp_s : default_ramp_s});
  }
  out.resolution = resolve(out.raw, table);
  if (!out.resolution.unknown.empty())
    out.warnings.push_back(fmt::format(
        "{} phoneme(s) not in data/speech/{}.json, animated as a neutral consonant: {}",
        out.resolution.unknown.size(), table.language(), describe_unknown(out.resolution.unknown)));
  return out;
}

}  // namespace rostro::speech
