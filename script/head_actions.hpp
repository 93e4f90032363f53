#pragma once
// Head actions: nod, shake, tilt, turn (and still, a window without idle motion), frame by
// frame, plus the idle head noise of speech/ (seed004 6.6 rule 3: small smooth noise when
// nothing else moves the head). Overlapping actions add.
//   nod:   pitch = A sin^2(pi n u)             (down and back, n times; u = 0..1 over the action)
//   shake: yaw   = A sin(2 pi n u) sin(pi u)   (side to side, n times, fading in and out)
//   tilt:  roll  = +-A, ramped in and out over `ramp` (smoothstep)
//   turn:  yaw/pitch/roll to the target, ramped; held to the end of the scene without a duration

#include <cstdint>
#include <vector>

#include "script/storyboard.hpp"
#include "speech/behaviour.hpp"

namespace rostro::script {

struct HeadFrame {
  Direction action;       // the sum of the scripted actions, degrees
  double activity = 0.0;  // 0..1: a scripted action (or still) is on, ramped over 0.3 s
  Direction noise;        // idle noise, degrees (zero when the scene has none)
};

class HeadActions {
 public:
  // `noise`: idle head motion on (the scene's seed gives `rostro speak`'s noise for it).
  HeadActions(const std::vector<HeadAction>& actions, long frames, double fps,
              const speech::HeadSettings& settings, std::uint64_t seed, bool noise);

  const HeadFrame& frame(long k) const { return frames_.at(static_cast<std::size_t>(k)); }
  bool moves_head() const { return moves_; }

  // A single action's angles at time t (degrees), for tests.
  static Direction pose(const HeadAction& a, double t);

 private:
  std::vector<HeadFrame> frames_;
  bool moves_ = false;
};

}  // namespace rostro::script
