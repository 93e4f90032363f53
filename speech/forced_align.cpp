#include "speech/forced_align.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "facecore/error.hpp"
#include "speech/dtw.hpp"

namespace rostro::speech {
namespace {

// For each reference frame, the mean recording frame the path matches it with.
std::vector<double> frame_map(const WarpPath& path, int reference_frames) {
  std::vector<double> sum(reference_frames, 0.0);
  std::vector<int> count(reference_frames, 0);
  for (const auto& [i, j] : path.steps) {
    sum[i] += j;
    ++count[i];
  }
  for (int i = 0; i < reference_frames; ++i) sum[i] /= std::max(1, count[i]);
  return sum;
}

// Recording time of reference time `t`, interpolating between frames. Frame i starts at
// i x hop in both signals, so the analysis window's own offset cancels.
double carry(double t, const std::vector<double>& map, double hop_s) {
  const double x = t / hop_s;
  const int last = static_cast<int>(map.size()) - 1;
  if (x <= 0) return map.front() * hop_s;
  if (x >= last) return map.back() * hop_s;
  const int i = static_cast<int>(x);
  const double f = x - i;
  return ((1 - f) * map[i] + f * map[i + 1]) * hop_s;
}

// Mean distance between the frames `path` matches, over recording frames that are speech.
double speech_distance(const WarpPath& path, const Features& a, const Features& b,
                       const std::vector<bool>& speech) {
  double sum = 0.0;
  long count = 0;
  for (const auto& [i, j] : path.steps)
    if (speech[static_cast<std::size_t>(j)]) {
      sum += frame_distance(a, i, b, j);
      ++count;
    }
  return count ? sum / static_cast<double>(count) : 0.0;
}

// Voice activity per analysis frame: louder than a quarter of the way from the recording's
// noise floor (its quietest 5 %, but no lower than 60 dB under the peak: digital silence
// is no floor) to its loudest frame.
std::vector<bool> voice_activity(const std::vector<float>& energy_db) {
  std::vector<float> sorted = energy_db;
  std::sort(sorted.begin(), sorted.end());
  const float peak = sorted.back();
  const float floor = std::max(sorted[sorted.size() / 20], peak - 60.0f);
  const float threshold = floor + 0.25f * (peak - floor);
  std::vector<bool> voiced(energy_db.size());
  for (std::size_t j = 0; j < energy_db.size(); ++j) voiced[j] = energy_db[j] > threshold;
  return voiced;
}

bool is_pause(const RawPhoneme& p) {
  return !p.symbol.empty() && p.symbol[0] == '_';
}

// Runs of voiced frames that fall inside the aligned pauses, joined across gaps shorter than
// `gap_s`, kept when their voiced frames add up to `min_s`.
std::vector<std::pair<double, double>> uncovered_speech(const std::vector<RawPhoneme>& aligned,
                                                        const std::vector<bool>& voiced,
                                                        double hop_s, double min_s, double gap_s) {
  std::vector<std::pair<double, double>> out;
  double start = -1.0, last = -1.0, voiced_s = 0.0;
  auto close = [&] {
    if (start >= 0.0 && voiced_s >= min_s) out.emplace_back(start, last + hop_s);
    start = -1.0;
    voiced_s = 0.0;
  };
  std::size_t k = 0;
  for (std::size_t j = 0; j < voiced.size(); ++j) {
    const double t = static_cast<double>(j) * hop_s;
    while (k + 1 < aligned.size() && aligned[k].end_s <= t) ++k;
    if (!voiced[j] || !is_pause(aligned[k])) continue;
    if (start >= 0.0 && t - last > gap_s) close();
    if (start < 0.0) start = t;
    last = t;
    voiced_s += hop_s;
  }
  close();
  return out;
}

Features reversed(const Features& f) {
  Features out = f;
  for (int i = 0; i < f.frames; ++i)
    std::copy(f.row(f.frames - 1 - i), f.row(f.frames - 1 - i) + f.dims, out.row(i));
  return out;
}

}  // namespace

Alignment align_reference(const Audio& recording, const Audio& reference,
                          const std::vector<RawPhoneme>& reference_phonemes,
                          const AlignmentOptions& options) {
  if (reference_phonemes.empty()) throw InputError("the transcript gives no phonemes to align");
  MfccOptions features = options.features;
  features.high_hz = band_top(recording, reference, features.high_hz);
  const Features a = mfcc(reference, features);
  const Features b = mfcc(recording, features);

  std::vector<bool> speech = voice_activity(frame_energy_db(recording, features));
  speech.resize(static_cast<std::size_t>(b.frames), false);

  const WarpPath path = warp(a, b, options.warping);
  // The check's yardstick: the same sounds in the wrong order. It grows with how far the
  // voice, the microphone and the noise put the recording from the reference, which the
  // ratio so divides out in part.
  const Features backwards = reversed(a);
  const double yardstick =
      speech_distance(warp(backwards, b, options.warping), backwards, b, speech);
  Alignment out;
  out.match_ratio = yardstick > 0.0 ? speech_distance(path, a, b, speech) / yardstick : 0.0;
  if (out.match_ratio > options.max_match_ratio)
    throw InputError(fmt::format(
        "the recording does not match the transcript (match ratio {:.2f}, above {:.2f}; "
        "readings of the right text measure 0.2-0.8): check the text and --lang",
        out.match_ratio, options.max_match_ratio));

  const std::vector<double> map = frame_map(path, a.frames);
  const double end = recording.duration_s();
  out.phonemes = reference_phonemes;
  double previous = 0.0;
  for (RawPhoneme& p : out.phonemes) {
    p.start_s = std::clamp(carry(p.start_s, map, a.hop_s), previous, end);
    previous = p.start_s;
  }
  // A recording may begin with silence where the reference begins with speech.
  if (out.phonemes.front().start_s > 0.0)
    out.phonemes.insert(out.phonemes.begin(), {"_", 0.0, 0.0, -1});
  for (std::size_t k = 0; k < out.phonemes.size(); ++k)
    out.phonemes[k].end_s = k + 1 < out.phonemes.size() ? out.phonemes[k + 1].start_s : end;
  out.uncovered_speech = uncovered_speech(out.phonemes, speech, b.hop_s, options.uncovered_min_s,
                                          options.uncovered_gap_s);
  return out;
}

// The reference with `pad_s` of silence before and after, so a recording's own leading and
// trailing silence (or room noise) has something to match other than the first and last
// phonemes.
Synthesis padded(Synthesis s, double pad_s) {
  const auto pad = static_cast<std::size_t>(pad_s * s.audio.sample_rate);
  const double pad_time = static_cast<double>(pad) / s.audio.sample_rate;
  s.audio.samples.insert(s.audio.samples.begin(), pad, 0);
  s.audio.samples.insert(s.audio.samples.end(), pad, 0);
  for (RawPhoneme& p : s.phonemes) {
    p.start_s += pad_time;
    p.end_s += pad_time;
  }
  s.phonemes.insert(s.phonemes.begin(), {"_", 0.0, pad_time, -1});
  s.phonemes.push_back({"_", s.phonemes.back().end_s, s.audio.duration_s(), -1});
  return s;
}

// Seconds from the first voiced analysis frame to the last.
double voiced_span_s(const Audio& audio, const MfccOptions& features) {
  const std::vector<bool> voiced = voice_activity(frame_energy_db(audio, features));
  const auto first = std::find(voiced.begin(), voiced.end(), true);
  const auto last = std::find(voiced.rbegin(), voiced.rend(), true);
  if (first == voiced.end()) return 0.0;
  return static_cast<double>((voiced.rend() - last) - (first - voiced.begin())) * features.hop_s;
}

constexpr int kDefaultRateWpm = 175;  // espeak-ng's

Alignment align_transcript(const Audio& recording, const std::string& clean_text,
                           const AlignmentOptions& options) {
  const double recording_span = voiced_span_s(recording, options.features);
  std::optional<Alignment> best;
  std::optional<InputError> refusal;
  const bool has_variant = options.reference.voice.find('+') != std::string::npos;
  for (const std::string& variant : options.voice_variants) {
    if (has_variant && !variant.empty()) continue;  // a variant the user chose is kept
    SynthOptions voice = options.reference;
    voice.voice += variant;
    Synthesis said = synthesize(clean_text, voice);
    // A reading much slower or faster than espeak-ng's is said again at the reading's pace,
    // so the warping has less to stretch (each stretch step pays the penalty).
    const double said_span = voiced_span_s(said.audio, options.features);
    if (options.match_tempo && options.reference.rate_wpm == 0 && said_span > 0 &&
        recording_span > 0) {
      const double tempo = said_span / recording_span;
      if (tempo < 0.85 || tempo > 1.18) {
        voice.rate_wpm =
            std::clamp(static_cast<int>(std::lround(kDefaultRateWpm * tempo)), 80, 450);
        said = synthesize(clean_text, voice);
      }
    }
    const Synthesis reference = padded(std::move(said), options.reference_pad_s);
    try {
      Alignment a = align_reference(recording, reference.audio, reference.phonemes, options);
      a.reference_voice = voice.voice;
      if (!best || a.match_ratio < best->match_ratio) best = std::move(a);
    } catch (const InputError& e) {
      refusal = e;  // another variant may still match
    }
  }
  if (!best) throw refusal.value_or(InputError("no reference voice to align with"));
  return std::move(*best);
}

}  // namespace rostro::speech
