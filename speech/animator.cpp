#include "speech/animator.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "facecore/option_check.hpp"

namespace rostro::speech {
namespace {

constexpr double kAuPerDegree = std::numbers::pi / 180.0 * 1e5;  // FAP angle unit: 1e-5 rad

int key_viseme(const Key& key, const std::vector<Phoneme>& p) {
  if (key.kind == KeyKind::Vowel) return p[static_cast<std::size_t>(key.vowel)].viseme;
  if (key.consonant >= 0) return p[static_cast<std::size_t>(key.consonant)].viseme;
  return 0;
}

}  // namespace

void AnimationOptions::validate() const {
  OptionCheck("AnimationOptions")
      .positive("fps", fps)
      .within("base_expression", base_expression, 0, kExpressionCount - 1)
      .within("base_intensity", base_intensity, 0, 1);
}

Animator::Animator(std::vector<Phoneme> phonemes, double duration_s,
                   std::vector<EmotionEvent> emotions, const ExpressionLibrary& library,
                   const KeyShapes& shapes, const BehaviourSettings& behaviour,
                   const AnimationOptions& options)
    : phonemes_(std::move(phonemes)),
      options_(validated(options)),
      shapes_(shapes),
      behaviour_(behaviour) {
  for (int e = 0; e < kExpressionCount; ++e)
    expressions_[static_cast<std::size_t>(e)] = low_level_vector(library.expression(e));

  keys_ = plan_keys(phonemes_, options_.planner);
  key_shapes_.reserve(keys_.size());
  for (const Key& key : keys_) key_shapes_.push_back(shapes_.shape(key, phonemes_));
  const long frames = frame_count_for(duration_s, options_.fps);
  blends_ = sample_keys(keys_, frames, options_.fps);
  forced_closures_ = ensure_bilabial_closures(blends_, keys_, phonemes_, options_.fps);

  // Emotion segments: each event ramps from wherever the face is at its time.
  std::stable_sort(
      emotions.begin(), emotions.end(),
      [](const EmotionEvent& a, const EmotionEvent& b) { return a.time_s < b.time_s; });
  const auto target = [&](int expression, double intensity) {
    EmotionState s;
    s.expression = expression;
    s.activation = expression == 0 ? 0.0 : intensity;
    for (std::size_t i = 0; i < s.e.size(); ++i)
      s.e[i] = intensity * expressions_[static_cast<std::size_t>(expression)][i];
    return s;
  };
  const EmotionState base = target(options_.base_expression, options_.base_intensity);
  segments_.push_back(Segment{-1e300, 0.0, base, base});
  for (const EmotionEvent& ev : emotions) {
    const EmotionState from = emotion_at(ev.time_s);
    segments_.push_back(
        Segment{ev.time_s, std::max(0.0, ev.ramp_s), from, target(ev.expression, ev.intensity)});
  }

  const std::uint64_t seed = options_.seed;
  if (options_.blinks) blink_ = blink_track(frames, options_.fps, behaviour_.blink, seed * 3 + 11);
  if (options_.saccades)
    gaze_ = saccade_track(frames, options_.fps, behaviour_.saccade, seed * 3 + 12);
  if (options_.head_motion)
    head_ = head_track(frames, options_.fps, behaviour_.head, seed * 3 + 13);

  for (int id = 3; id <= 18; ++id) mouth_[static_cast<std::size_t>(id)] = true;
  for (int id = 43; id <= 47; ++id) mouth_[static_cast<std::size_t>(id)] = true;
  for (int id = 51; id <= 60; ++id) mouth_[static_cast<std::size_t>(id)] = true;
  for (int id : shapes_.closure_faps()) closure_[static_cast<std::size_t>(id)] = true;

  // One mask for every frame: all FAPs any source can move, so players see a steady set.
  std::array<bool, kFapCount + 1> used{};
  for (int id : shapes_.viseme_faps()) used[static_cast<std::size_t>(id)] = true;
  for (const auto& e : expressions_)
    for (int id = 3; id <= kFapCount; ++id)
      if (fap(e, id) != 0.0) used[static_cast<std::size_t>(id)] = true;
  if (options_.blinks)
    for (int id = 19; id <= 22; ++id) used[static_cast<std::size_t>(id)] = true;
  if (options_.saccades)
    for (int id = 23; id <= 26; ++id) used[static_cast<std::size_t>(id)] = true;
  if (options_.head_motion)
    for (int id = 48; id <= 50; ++id) used[static_cast<std::size_t>(id)] = true;
  for (int id = 3; id <= kFapCount; ++id)
    if (used[static_cast<std::size_t>(id)]) mask_ids_.push_back(id);
}

Animator::EmotionState Animator::emotion_at(double t) const {
  const auto it = std::upper_bound(segments_.begin(), segments_.end(), t,
                                   [](double x, const Segment& s) { return x < s.start; });
  const Segment& s = *(it == segments_.begin() ? it : std::prev(it));
  const double r = s.ramp > 0.0 ? std::clamp((t - s.start) / s.ramp, 0.0, 1.0) : 1.0;
  EmotionState out;
  for (std::size_t i = 0; i < out.e.size(); ++i)
    out.e[i] = s.from.e[i] + r * (s.to.e[i] - s.from.e[i]);
  out.activation = s.from.activation + r * (s.to.activation - s.from.activation);
  out.expression = r >= 0.5 ? s.to.expression : s.from.expression;
  return out;
}

FapVector Animator::viseme_part(long k) const {
  const FrameBlend& b = blends_.at(static_cast<std::size_t>(k));
  const FapVector zero{};
  const FapVector& a = b.from >= 0 ? key_shapes_[static_cast<std::size_t>(b.from)] : zero;
  const FapVector& c = b.to >= 0 ? key_shapes_[static_cast<std::size_t>(b.to)] : zero;
  FapVector v{};
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = (1.0 - b.weight) * a[i] + b.weight * c[i];
  return v;
}

FapFrame Animator::frame(long k) const {
  const double t = static_cast<double>(k) / options_.fps;
  const FrameBlend& b = blends_.at(static_cast<std::size_t>(k));
  const FapVector v = viseme_part(k);
  const double closing = closure_weight(b, keys_, phonemes_);
  const EmotionState em = emotion_at(t);
  const double ew = behaviour_.expression_weight * em.activation;

  FapVector out{};
  for (int id = 3; id <= kFapCount; ++id) {
    const auto i = static_cast<std::size_t>(id);
    double x = fap(em.e, id) + fap(v, id);
    if (mouth_[i]) {
      x = (1.0 - ew) * fap(v, id) + behaviour_.expression_weight * fap(em.e, id);
      if (closure_[i]) x = (1.0 - closing) * x + closing * fap(v, id);
    }
    fap(out, id) = x;
  }
  if (!blink_.empty()) {
    const double c = blink_[static_cast<std::size_t>(k)];
    for (int id : {19, 20}) fap(out, id) += c * (behaviour_.blink.closed_top_irisd - fap(out, id));
    for (int id : {21, 22})
      fap(out, id) += c * (behaviour_.blink.closed_bottom_irisd - fap(out, id));
  }
  if (!gaze_.empty()) {
    const Gaze& g = gaze_[static_cast<std::size_t>(k)];
    for (int id : {23, 24}) fap(out, id) += g.yaw_deg * kAuPerDegree;
    for (int id : {25, 26}) fap(out, id) += g.pitch_deg * kAuPerDegree;
  }
  if (!head_.empty()) {
    const HeadPose& h = head_[static_cast<std::size_t>(k)];
    fap(out, 48) += h.pitch_deg * kAuPerDegree;
    fap(out, 49) += h.yaw_deg * kAuPerDegree;
    fap(out, 50) += h.roll_deg * kAuPerDegree;
  }

  FapFrame f;
  f.index = k;
  f.time_s = t;
  for (int id : mask_ids_) f.set(id, fap(out, id));
  if (options_.high_level) {
    VisemeParams vp;
    vp.select1 = b.from >= 0 ? key_viseme(keys_[static_cast<std::size_t>(b.from)], phonemes_) : 0;
    vp.select2 = b.to >= 0 ? key_viseme(keys_[static_cast<std::size_t>(b.to)], phonemes_) : 0;
    vp.blend = static_cast<int>(std::lround(63.0 * (1.0 - b.weight)));
    f.set_viseme(vp);
    ExpressionParams ep;
    ep.select1 = em.expression;
    ep.intensity1 = static_cast<int>(std::lround(63.0 * std::clamp(em.activation, 0.0, 1.0)));
    f.set_expression(ep);
  }
  return f;
}

FapStream Animator::stream(const std::string& name) const {
  FapStream s;
  s.header.name = name;
  s.header.fps = options_.fps;
  s.header.frame_count = frame_count();
  s.frames.reserve(static_cast<std::size_t>(frame_count()));
  for (long k = 0; k < frame_count(); ++k) s.frames.push_back(frame(k));
  return s;
}

}  // namespace rostro::speech
