#pragma once
// Eye Behaviour Generation (seed004 6.5, the GDL plus pursuit), frame by frame:
// - natural saccades from speech/'s statistical model, in a window, with a style that changes
//   the model's interval, magnitude and direction (the seed's Behavioural Database);
// - look (a saccade to a target, held, then back to the camera when the look has a duration)
//   and pursuit (smooth following of a moving target, after a catch-up saccade);
// - blinks: natural (speech/'s random intervals) in a window, or one at a scheduled time;
//   eyes closed or half closed over a window;
// - the head follows large gaze shifts: beyond 10 degrees it takes 60 % of the rest, with a
//   lag (0.15 s), and the eyes counter-rotate so the gaze stays on target;
// - the upper lids follow the eyes' vertical gaze (lower when looking down).

#include <cstdint>
#include <vector>

#include "script/storyboard.hpp"
#include "speech/behaviour.hpp"

namespace rostro::script {

struct EyeFrame {
  double yaw_deg = 0.0, pitch_deg = 0.0;            // eyes in the head: scripted gaze + saccades
  double head_yaw_deg = 0.0, head_pitch_deg = 0.0;  // the head's share of the gaze
  double head_activity = 0.0;                       // 0..1: how much the head is driven by gaze
  double lid_irisd = 0.0;     // upper lids' follow of vertical gaze (FAP 19/20 units)
  double lid_activity = 0.0;  // 0..1
  double closure = 0.0;       // 0 open .. 1 shut: blinks and closes, the larger wins
};

class EyeBehaviour {
 public:
  // `seed`: the scene's seed; natural blinks and saccades use the same streams as `rostro
  // speak` with that seed, so a generated viseme script reproduces its eyes exactly.
  EyeBehaviour(const std::vector<EyeAction>& actions, long frames, double fps,
               const speech::BehaviourSettings& settings, std::uint64_t seed);

  const EyeFrame& frame(long k) const { return frames_.at(static_cast<std::size_t>(k)); }
  bool moves_lids() const { return moves_lids_; }
  bool moves_eyes() const { return moves_eyes_; }
  bool moves_head() const { return moves_head_; }

  // Degrees of lid travel per degree of vertical gaze, and the head's share (tests, docs).
  static constexpr double kLidPerDegreeDown = 16.0, kLidPerDegreeUp = 8.0;
  static constexpr double kHeadFreeDeg = 10.0, kHeadShare = 0.6, kHeadLagS = 0.15;

 private:
  void add_saccades(const EyeAction& a, const speech::BehaviourSettings& settings,
                    std::uint64_t seed);
  void add_blinks(const EyeAction& a, const speech::BehaviourSettings& settings,
                  std::uint64_t seed);
  void add_closure(const EyeAction& a, const speech::BlinkSettings& blink);
  void add_gaze(const std::vector<const EyeAction*>& gaze, const speech::SaccadeSettings& s);

  double fps_;
  std::vector<EyeFrame> frames_;
  bool moves_lids_ = false, moves_eyes_ = false, moves_head_ = false;
};

}  // namespace rostro::script
