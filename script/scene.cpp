#include "script/scene.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "facecore/error.hpp"
#include "facecore/option_check.hpp"
#include "speech/audio_file.hpp"
#include "speech/key_sampler.hpp"
#include "speech/pipeline.hpp"

namespace rostro::script {
namespace {

constexpr double kSpeechEdgeS = 0.15;  // speech's hold on the mouth ramps over this at each edge

// The latest time an entry needs the scene to reach: its end, or its start when open-ended.
template <typename Item>
double reach(const Item& item) {
  return std::isfinite(item.end) ? item.end : item.at;
}

}  // namespace

std::vector<ResolvedSpeech> resolve_speech(const Storyboard& board,
                                           const speech::BehaviourSettings& behaviour,
                                           std::vector<std::string>& warnings) {
  std::vector<ResolvedSpeech> out;
  for (const SpeechItem& item : board.speech) {
    ResolvedSpeech r;
    r.origin = item.origin;
    r.at = item.at;
    r.base_expression = item.base_expression;
    r.base_intensity = item.base_intensity;
    try {
      if (item.has_visemes) {
        r.phonemes = item.visemes;
        r.emotions = item.emotions;
        if (!item.sound.empty()) r.audio = speech::read_audio(item.sound);
        r.duration_s = item.duration >= 0         ? item.duration
                       : !r.audio.samples.empty() ? r.audio.duration_s()
                                                  : r.phonemes.back().end_s;
      } else {
        const speech::SpeechRequest request{.text = item.text,
                                            .language = item.language,
                                            .voice = item.voice,
                                            .rate_wpm = item.rate_wpm,
                                            .pho = item.pho,
                                            .audio = item.sound};
        speech::PreparedSpeech prepared = speech::prepare_speech(request, behaviour.default_ramp_s);
        for (const std::string& w : prepared.warnings) warnings.push_back(item.origin + ": " + w);
        r.phonemes = std::move(prepared.resolution.phonemes);
        r.duration_s = prepared.duration_s;
        r.audio = std::move(prepared.audio);
        r.emotions = std::move(prepared.emotions);
      }
    } catch (const InputError& e) {
      throw InputError(item.origin + ": " + e.what());
    }
    if (r.phonemes.empty()) throw InputError(item.origin + ": no phonemes to animate");
    out.push_back(std::move(r));
  }
  return out;
}

void SceneOptions::validate() const {
  OptionCheck("SceneOptions").positive("fps", fps).within("fps", fps, 0, kMaxFps);
}

Scene::Scene(const Storyboard& board, std::vector<ResolvedSpeech> speech,
             const ExpressionLibrary& library, const speech::KeyShapes& shapes,
             const speech::BehaviourSettings& behaviour, const SceneOptions& options)
    : options_(validated(options)) {
  const double fps = options_.fps;
  // 1. Utterances on the frame grid, one after another, never overlapping.
  speech::AnimationOptions animation;
  animation.fps = fps;
  animation.blinks = animation.saccades = animation.head_motion = false;
  double previous_end = 0.0;
  long next_free = 0;
  int sample_rate = 0;
  std::string previous;
  for (ResolvedSpeech& s : speech) {
    const double at = s.at >= 0 ? s.at : previous_end;
    if (!previous.empty() && at < previous_end - 1e-9)
      throw InputError(fmt::format(
          "{}: speech overlaps speech: it starts at {:.3f} s, before {} ends at {:.3f} s", s.origin,
          at, previous, previous_end));
    Utterance u;
    u.first_frame = std::max(std::lround(at * fps), next_free);
    animation.base_expression = s.base_expression;
    animation.base_intensity = s.base_intensity;
    u.animator = std::make_unique<speech::Animator>(s.phonemes, s.duration_s, s.emotions, library,
                                                    shapes, behaviour, animation);
    if (!s.audio.samples.empty()) {
      if (sample_rate != 0 && s.audio.sample_rate != sample_rate)
        throw InputError(fmt::format("{}: its audio is {} Hz but earlier speech is {} Hz", s.origin,
                                     s.audio.sample_rate, sample_rate));
      sample_rate = s.audio.sample_rate;
    }
    previous_end = static_cast<double>(u.first_frame) / fps + s.duration_s;
    next_free = u.first_frame + u.animator->frame_count();
    previous = s.origin;
    duration_s_ = std::max(duration_s_, previous_end);
    u.speech = std::move(s);
    utterances_.push_back(std::move(u));
  }

  // 2. The scene's length: the longest part, or storyboard.duration.
  duration_s_ = std::max(duration_s_, board.duration);
  for (const auto& e : board.expressions) duration_s_ = std::max(duration_s_, reach(e));
  for (const auto& e : board.eyes) duration_s_ = std::max(duration_s_, reach(e));
  for (const auto& h : board.head) duration_s_ = std::max(duration_s_, reach(h));
  frames_ = std::max(speech::frame_count_for(duration_s_, fps), next_free);
  if (frames_ == 0)
    throw InputError(board.file.string() +
                     ": the scene has no length: give speech, timed entries or duration = S");

  // 3. The other layers.
  expressions_ = std::make_unique<ExpressionTrack>(board.expressions, library);
  eyes_ = std::make_unique<EyeBehaviour>(board.eyes, frames_, fps, behaviour, options_.seed);
  std::vector<HeadAction> actions;
  bool noise = true;
  for (const HeadAction& h : board.head) {
    if (h.kind == HeadKind::Still && h.at <= 0.0 && !std::isfinite(h.end))
      noise = false;  // a still head all through: no idle motion at all
    else
      actions.push_back(h);
  }
  head_ =
      std::make_unique<HeadActions>(actions, frames_, fps, behaviour.head, options_.seed, noise);
  sync_ = std::make_unique<FapSynchronizer>(behaviour, shapes.closure_faps());

  // 4. One mask for every frame: every FAP some layer can move.
  std::array<bool, kFapCount + 1> used{};
  for (const Utterance& u : utterances_) {
    const FapFrame f = u.animator->frame(0);
    for (int id = 3; id <= kFapCount; ++id) used[static_cast<std::size_t>(id)] |= f.has(id);
  }
  for (int id : expressions_->faps()) used[static_cast<std::size_t>(id)] = true;
  const auto use = [&](int first, int last, bool on) {
    for (int id = first; id <= last && on; ++id) used[static_cast<std::size_t>(id)] = true;
  };
  use(19, 22, eyes_->moves_lids());
  use(23, 26, eyes_->moves_eyes());
  use(48, 50, head_->moves_head() || eyes_->moves_head());
  for (int id = 3; id <= kFapCount; ++id)
    if (used[static_cast<std::size_t>(id)]) mask_.push_back(id);
}

Scene::~Scene() = default;

FapFrame Scene::frame(long k) const {
  const double t = static_cast<double>(k) / options_.fps;
  FrameLayers layers;
  FapVector speech_v{}, viseme_v{};
  // The utterance holding frame k, if any.
  const auto it = std::upper_bound(utterances_.begin(), utterances_.end(), k,
                                   [](long x, const Utterance& u) { return x < u.first_frame; });
  if (it != utterances_.begin()) {
    const Utterance& u = *std::prev(it);
    const long j = k - u.first_frame;
    if (j < u.animator->frame_count()) {
      const speech::Animator& a = *u.animator;
      speech_v = speech::low_level_vector(a.frame(j));
      viseme_v = a.viseme_part(j);
      layers.speech = &speech_v;
      layers.viseme = &viseme_v;
      layers.closing =
          speech::closure_weight(a.blends()[static_cast<std::size_t>(j)], a.keys(), a.phonemes());
      const double local = static_cast<double>(j) / options_.fps;
      layers.speech_activity =
          std::clamp(std::min(local, u.speech.duration_s - local) / kSpeechEdgeS, 0.0, 1.0);
    }
  }
  expressions_->sample(t, layers.expression, layers.expression_activity);
  layers.eyes = eyes_->frame(k);
  layers.head = head_->frame(k);
  const FapVector out = sync_->merge(layers);

  FapFrame f;
  f.index = k;
  f.time_s = t;
  for (int id : mask_) f.set(id, speech::fap(out, id));
  return f;
}

FapStream Scene::stream(const std::string& name) const {
  FapStream s;
  s.header.name = name;
  s.header.fps = options_.fps;
  s.header.frame_count = frames_;
  s.frames.reserve(static_cast<std::size_t>(frames_));
  for (long k = 0; k < frames_; ++k) s.frames.push_back(frame(k));
  return s;
}

speech::Audio Scene::audio() const {
  speech::Audio out;
  out.sample_rate = 22050;
  for (const Utterance& u : utterances_)
    if (!u.speech.audio.samples.empty()) out.sample_rate = u.speech.audio.sample_rate;
  out.samples.assign(static_cast<std::size_t>(std::lround(duration_s_ * out.sample_rate)), 0);
  for (const Utterance& u : utterances_) {
    const auto first = static_cast<std::size_t>(
        std::lround(static_cast<double>(u.first_frame) / options_.fps * out.sample_rate));
    const auto& samples = u.speech.audio.samples;
    if (out.samples.size() < first + samples.size()) out.samples.resize(first + samples.size(), 0);
    for (std::size_t i = 0; i < samples.size(); ++i) {
      const int mixed = out.samples[first + i] + samples[i];
      out.samples[first + i] = static_cast<std::int16_t>(std::clamp(mixed, -32768, 32767));
    }
  }
  return out;
}

std::vector<speech::Phoneme> Scene::phonemes() const {
  std::vector<speech::Phoneme> out;
  double t = 0.0;
  auto silence_until = [&](double end) {
    if (end <= t) return;
    speech::Phoneme gap;
    gap.symbol = "_";
    gap.cls = speech::PhonemeClass::Silence;
    gap.start_s = t;
    gap.end_s = end;
    out.push_back(gap);
    t = end;
  };
  for (const Utterance& u : utterances_) {
    const double start = static_cast<double>(u.first_frame) / options_.fps;
    silence_until(start);
    for (speech::Phoneme p : u.speech.phonemes) {
      p.start_s += start;
      p.end_s += start;
      out.push_back(p);
      t = std::max(t, p.end_s);
    }
  }
  silence_until(duration_s_);
  return out;
}

}  // namespace rostro::script
