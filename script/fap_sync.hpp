#pragma once
// FAP Synchronization (seed004 6.6): merges the speech, expression, eye and head layers of one
// frame into one FAP vector. With `a` the activity (0..1) of a layer on a FAP, two layers X and
// Y weighted wX + wY = 1 mix as
//     X (1 - wY aY) + Y (1 - wX aX)
// which is wX X + wY Y when both act fully and either layer alone when the other is idle:
// 1. mouth FAPs (3-18, 43-47, 51-60): expression 25 %, speech 75 %, the seed's (E + 3V) / 4
//    (while a bilabial closes, the jaw and vertical lip FAPs follow the viseme, so p/b/m close
//    under any scripted expression); the speech layer already mixed its own emotion tags the
//    same way (speech/animator.hpp);
// 2. other FAPs: the speech layer's emotions plus the scripted expressions;
// 3. upper eyelids (19, 20): eye behaviour 25 %, expression 75 %; then blinks and closes
//    shut the lids on top (a closure of 1 is fully shut whatever the expression);
// 4. eyeballs (23-26): the eye behaviour's angles are added;
// 5. head (48-50): gaze-driven head motion 25 % against the expression's 75 %, plus the
//    scripted head actions; the idle noise fades out while either moves the head.

#include "script/eye_behaviour.hpp"
#include "script/head_actions.hpp"
#include "speech/behaviour.hpp"
#include "speech/key_shapes.hpp"

namespace rostro::script {

using speech::FapVector;

struct FrameLayers {
  const FapVector* speech = nullptr;  // the speech layer (visemes + its emotions), or none
  const FapVector* viseme = nullptr;  // the visemes alone (for bilabial closures)
  double speech_activity = 0.0;       // 0..1, ramped at each utterance's edges
  double closing = 0.0;               // 0..1: how much the mouth is closing for p/b/m
  FapVector expression{};
  FapVector expression_activity{};
  EyeFrame eyes;
  HeadFrame head;
};

class FapSynchronizer {
 public:
  FapSynchronizer(const speech::BehaviourSettings& behaviour, const std::vector<int>& closure_faps);
  FapVector merge(const FrameLayers& layers) const;

  static bool is_mouth(int id);
  // X (1 - wY aY) + Y (1 - wX aX): the weighted sum of two layers with activities.
  static double mix(double x, double ax, double wx, double y, double ay) {
    return x * (1.0 - (1.0 - wx) * ay) + y * (1.0 - wx * ax);
  }

 private:
  speech::BehaviourSettings behaviour_;
  std::array<bool, kFapCount + 1> closure_{};
};

}  // namespace rostro::script
