#include "speech/pipeline.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "facecore/error.hpp"
#include "speech/audio_file.hpp"
#include "speech/espeak_synth.hpp"
#include "speech/forced_align.hpp"
#include "speech/pho_reader.hpp"
#include "speech/phone_recognizer.hpp"
#include "speech/speech_presence.hpp"

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
  if (request.pho.empty() && request.text.empty() && !request.audio.empty()) {
    if (table.language() != "en")
      throw InputError(
          "--audio without a transcript works for English only (PocketSphinx "
          "en-us); give the " +
          table.language() + " recording's transcript (TEXT or --text-file)");
    out.recognition = Recognition::PhoneRecognition;
    out.audio = read_audio(request.audio);
    require_speech(out.audio, request.audio.string());
    out.duration_s = out.audio.duration_s();
    out.raw = recognize_phones(out.audio);
    const bool heard = std::any_of(out.raw.begin(), out.raw.end(), [&](const RawPhoneme& p) {
      const PhonemeInfo* info = table.find(p.symbol);
      return info && info->cls != PhonemeClass::Silence;
    });
    if (!heard)
      throw InputError(
          where(request.audio.string(), 0, "no speech recognised (silence, noise or music?)"));
  } else if (!request.pho.empty()) {
    out.recognition = Recognition::Pho;
    out.raw = read_pho(request.pho);
    const double pho_end = out.raw.back().end_s;
    if (!request.audio.empty()) {
      out.audio = read_audio(request.audio);
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
    out.voice = synth.voice;
    if (!request.audio.empty()) {
      out.recognition = Recognition::Alignment;
      out.audio = read_audio(request.audio);
      require_speech(out.audio, request.audio.string());
      AlignmentOptions align;
      align.reference = synth;
      Alignment aligned = align_transcript(out.audio, marked.clean, align);
      out.match_ratio = aligned.match_ratio;
      for (const auto& [from, to] : aligned.uncovered_speech)
        out.warnings.push_back(fmt::format(
            "{}: speech at {:.2f}-{:.2f} s that the transcript does not cover (a missing "
            "word or line?); the mouth rests there",
            request.audio.string(), from, to));
      if (aligned.match_ratio > align.doubtful_match_ratio)
        out.warnings.push_back(fmt::format(
            "the recording may not say the transcript (match ratio {:.2f}; readings of the "
            "right text measure 0.2-0.8, of another text 0.8-0.9): check the text and --lang",
            aligned.match_ratio));
      out.voice = aligned.reference_voice;
      out.raw = std::move(aligned.phonemes);
    } else {
      Synthesis s = synthesize(marked.clean, synth);
      out.audio = std::move(s.audio);
      out.raw = std::move(s.phonemes);
    }
    out.duration_s = out.audio.duration_s();
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
