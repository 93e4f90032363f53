#pragma once
// Eyes and head (seed004 6.5/6.6): blinks at natural random intervals, small saccades and
// head motion from smooth (Perlin-style gradient) noise. All seeded: the same seed gives the
// same face. Settings come from data/speech/behaviour.json.

#include <cstdint>
#include <filesystem>
#include <vector>

namespace rostro::speech {

struct BlinkSettings {
  double mean_interval_s = 3.6, min_interval_s = 1.0, interval_shape = 3.0;
  double close_s = 0.08, hold_s = 0.04, open_s = 0.16;
  double closed_top_irisd = 820, closed_bottom_irisd = 204;
};
struct SaccadeSettings {
  double mean_interval_s = 1.4, min_interval_s = 0.3, mean_amplitude_deg = 3.0,
         max_amplitude_deg = 9.0;
  double max_offset_deg = 8.0, return_probability = 0.45;
  double duration_base_s = 0.025, duration_per_deg_s = 0.0024;
};
struct HeadSettings {
  double base_frequency_hz = 0.22;
  int octaves = 2;
  double pitch_deg = 1.6, yaw_deg = 2.2, roll_deg = 0.8;
};
struct BehaviourSettings {
  BlinkSettings blink;
  SaccadeSettings saccade;
  HeadSettings head;
  double default_ramp_s = 0.3;
  double expression_weight = 0.25;  // seed004 Eq. 4.11: mouth = (E + 3V) / 4

  static BehaviourSettings load(const std::filesystem::path& path);
  static BehaviourSettings load_default();  // data/speech/behaviour.json
};

// Eyelid closure 0..1 per frame (1 = fully shut).
std::vector<double> blink_track(long frames, double fps, const BlinkSettings& s,
                                std::uint64_t seed);

struct Gaze {
  double yaw_deg = 0.0;    // positive: toward the face's left (FAP 23/24)
  double pitch_deg = 0.0;  // positive: down (FAP 25/26)
};
std::vector<Gaze> saccade_track(long frames, double fps, const SaccadeSettings& s,
                                std::uint64_t seed);

struct HeadPose {
  double pitch_deg = 0.0, yaw_deg = 0.0, roll_deg = 0.0;
};
std::vector<HeadPose> head_track(long frames, double fps, const HeadSettings& s,
                                 std::uint64_t seed);

// Smooth 1-D gradient noise in about [-1, 1], zero at integer x (Perlin 1985).
class GradientNoise {
 public:
  explicit GradientNoise(std::uint64_t seed);
  double operator()(double x) const;

 private:
  std::vector<double> gradients_;
};

}  // namespace rostro::speech
