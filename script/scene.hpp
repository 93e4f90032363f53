#pragma once
// The script-control pipeline (seed004 6.1): a storyboard's speech is synthesised or read
// (resolve_speech), then planned into layers (speech, expressions, eyes, head) that FAP
// Synchronization merges frame by frame. Frame k is scene time k / fps; the mixed speech
// audio starts at sample 0 on the same clock.

#include <memory>
#include <string>
#include <vector>

#include "facecore/expression_library.hpp"
#include "facecore/fap_frame.hpp"
#include "script/expression_track.hpp"
#include "script/eye_behaviour.hpp"
#include "script/fap_sync.hpp"
#include "script/head_actions.hpp"
#include "script/storyboard.hpp"
#include "speech/animator.hpp"
#include "speech/audio.hpp"
#include "speech/behaviour.hpp"
#include "speech/key_shapes.hpp"

namespace rostro::script {

// One utterance after recognition: phonemes, audio (empty without a sound) and emotions, in
// utterance time.
struct ResolvedSpeech {
  std::string origin;
  double at = -1.0;  // < 0: right after the previous utterance
  std::vector<speech::Phoneme> phonemes;
  double duration_s = 0.0;
  speech::Audio audio;
  std::vector<speech::EmotionEvent> emotions;
  int base_expression = 0;
  double base_intensity = 1.0;
};

// Synthesis (espeak-ng), .pho reading or the visemes as given. Warnings (unknown phonemes, a
// .pho longer than its WAV) are appended to `warnings`. Throws InputError for an unknown
// voice or language, unreadable files, bad markup.
std::vector<ResolvedSpeech> resolve_speech(const Storyboard& board,
                                           const speech::BehaviourSettings& behaviour,
                                           std::vector<std::string>& warnings);

struct SceneOptions {
  double fps = 25.0;
  std::uint64_t seed = 1;

  // Throws InputError for a frame rate outside (0, 1000]. Scene's constructor calls it.
  void validate() const;
};

class Scene {
 public:
  // Plans every layer. Throws InputError when speech overlaps speech or the scene has no
  // length. The library, shapes and behaviour must outlive the scene.
  Scene(const Storyboard& board, std::vector<ResolvedSpeech> speech,
        const ExpressionLibrary& library, const speech::KeyShapes& shapes,
        const speech::BehaviourSettings& behaviour, const SceneOptions& options);
  ~Scene();

  long frame_count() const { return frames_; }
  double fps() const { return options_.fps; }
  double duration_s() const { return duration_s_; }
  FapFrame frame(long k) const;
  FapStream stream(const std::string& name) const;
  // The utterances' audio placed at their start times, silence elsewhere, as long as the
  // scene (22050 Hz when no utterance has a sound).
  speech::Audio audio() const;
  // Every utterance's phonemes in scene time, with silences between and after them: what the
  // mouth says over the whole scene (for mouth cues).
  std::vector<speech::Phoneme> phonemes() const;

  struct Utterance {
    ResolvedSpeech speech;
    long first_frame = 0;
    std::unique_ptr<speech::Animator> animator;
  };
  const std::vector<Utterance>& utterances() const { return utterances_; }

 private:
  SceneOptions options_;
  double duration_s_ = 0.0;
  long frames_ = 0;
  std::vector<Utterance> utterances_;
  std::unique_ptr<ExpressionTrack> expressions_;
  std::unique_ptr<EyeBehaviour> eyes_;
  std::unique_ptr<HeadActions> head_;
  std::unique_ptr<FapSynchronizer> sync_;
  std::vector<int> mask_;
};

}  // namespace rostro::script
