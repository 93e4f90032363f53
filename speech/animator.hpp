#pragma once
// Output stage: turns planned keys, emotions and eye/head behaviour into FAP frames. Frame k
// is audio time k / fps from the first sample (the audio clock is the only clock). Mixing
// (seed004 6.6): mouth FAPs = (expression + 3 x viseme) / 4 at full emotion intensity
// (pure viseme with no emotion), except the jaw and vertical lip FAPs while a bilabial
// closes, which follow the viseme so p/b/m close under any expression; eyelids and brows
// come from the expression, with blinks closing the lids fully on top.

#include <cstdint>
#include <vector>

#include "facecore/expression_library.hpp"
#include "facecore/fap_frame.hpp"
#include "speech/behaviour.hpp"
#include "speech/coarticulation.hpp"
#include "speech/key_sampler.hpp"
#include "speech/key_shapes.hpp"
#include "speech/phoneme.hpp"

namespace rostro::speech {

struct EmotionEvent {
  double time_s = 0.0;     // when the ramp starts (audio time)
  int expression = 0;      // 0 neutral .. 6 surprise
  double intensity = 1.0;  // 0..1
  double ramp_s = 0.3;     // 0: a step
};

struct AnimationOptions {
  double fps = 25.0;
  bool blinks = true;
  bool saccades = true;
  bool head_motion = true;
  bool high_level = false;  // also write FAP 1 (viseme blend) and FAP 2 (expression)
  std::uint64_t seed = 1;
  PlannerOptions planner;
  int base_expression = 0;  // the emotion before the first event (0 neutral)
  double base_intensity = 1.0;

  // Throws InputError naming the first option out of range (fps <= 0, an intensity outside
  // 0..1, ...). Animator's constructor calls it.
  void validate() const;
};

class Animator {
 public:
  Animator(std::vector<Phoneme> phonemes, double duration_s, std::vector<EmotionEvent> emotions,
           const ExpressionLibrary& library, const KeyShapes& shapes,
           const BehaviourSettings& behaviour, const AnimationOptions& options);

  long frame_count() const { return static_cast<long>(blends_.size()); }
  double fps() const { return options_.fps; }
  FapFrame frame(long k) const;
  FapStream stream(const std::string& name) const;

  const std::vector<Phoneme>& phonemes() const { return phonemes_; }
  const std::vector<Key>& keys() const { return keys_; }
  const std::vector<FrameBlend>& blends() const { return blends_; }
  int forced_closures() const { return forced_closures_; }
  const KeyShapes& shapes() const { return shapes_; }
  // The viseme part of frame k alone (before emotion mixing), for tests.
  FapVector viseme_part(long k) const;

 private:
  struct EmotionState {
    FapVector e{};
    double activation = 0.0;
    int expression = 0;
  };
  struct Segment {
    double start = 0.0, ramp = 0.0;
    EmotionState from, to;
  };
  EmotionState emotion_at(double t) const;

  std::vector<Phoneme> phonemes_;
  AnimationOptions options_;
  const KeyShapes& shapes_;
  BehaviourSettings behaviour_;
  std::array<FapVector, kExpressionCount> expressions_{};
  std::vector<Key> keys_;
  std::vector<FapVector> key_shapes_;
  std::vector<FrameBlend> blends_;
  std::vector<Segment> segments_;
  std::vector<double> blink_;
  std::vector<Gaze> gaze_;
  std::vector<HeadPose> head_;
  std::vector<int> mask_ids_;
  std::array<bool, kFapCount + 1> mouth_{};
  std::array<bool, kFapCount + 1> closure_{};
  int forced_closures_ = 0;
};

}  // namespace rostro::speech
