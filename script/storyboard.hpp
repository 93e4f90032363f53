#pragma once
// The storyboard (seed004 6.2, the FDL): what a script directs, as plain data. A Lua script
// fills it (storyboard_reader.hpp); the planner (scene.hpp) turns it into FAP frames. Times are
// seconds from the start of the scene; angles are degrees; `origin` names the entry in messages
// ("story.lua: expressions[2]").

#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "speech/animator.hpp"
#include "speech/phoneme.hpp"

namespace rostro::script {

inline constexpr double kOpenEnd = std::numeric_limits<double>::infinity();

// A gaze or head direction. yaw: toward the character's own left (FAP 23/49 positive);
// pitch: down (FAP 25/48 positive); roll: toward the character's right (FAP 50).
struct Direction {
  double yaw_deg = 0.0;
  double pitch_deg = 0.0;
  double roll_deg = 0.0;
};

// One utterance: text for espeak-ng, a recording with its .pho, or (from a generated viseme
// script) the timed visemes themselves.
struct SpeechItem {
  std::string origin;
  double at = 0.0;
  std::string text;  // may carry emotion markup (docs/speech.md)
  std::string language = "es";
  std::string voice;  // empty: chosen from the language
  int rate_wpm = 0;
  std::filesystem::path sound;  // WAV, resolved against the script's folder
  std::filesystem::path pho;    // MBROLA .pho, resolved against the script's folder
  bool has_visemes = false;     // `visemes` below replace recognition
  std::vector<speech::Phoneme> visemes;
  double duration = -1.0;  // visemes: the utterance's length (< 0: the last viseme's end)
  std::vector<speech::EmotionEvent> emotions;  // visemes: emotion events in utterance time
  int base_expression = 0;
  double base_intensity = 1.0;
};

enum class Ease { Linear, Smooth };

struct ExpressionItem {
  std::string origin;
  int expression = 0;  // MPEG-4 expression_select 0..6
  double at = 0.0;
  double end = kOpenEnd;  // kOpenEnd: held to the end of the scene
  double intensity = 1.0;
  double ramp_in = 0.3;
  double ramp_out = 0.3;
  Ease ease = Ease::Linear;
};

enum class EyeKind { Look, Pursuit, Blink, Blinks, Saccades, Close };

struct EyeAction {
  std::string origin;
  EyeKind kind = EyeKind::Look;
  double at = 0.0;
  double end = kOpenEnd;          // look: returns to the camera at `end`; blinks/saccades: window
  std::vector<Direction> path;    // look: one target; pursuit: two or more, evenly spaced
  double amount = 1.0;            // close: 1 shut, 0.5 half closed
  double ramp = 0.1;              // close: seconds to shut and to open
  double rate_per_min = 0.0;      // blinks: 0 keeps data/speech/behaviour.json's rate
  std::string style = "talking";  // saccades: talking, listening, thinking
};

enum class HeadKind { Nod, Shake, Tilt, Turn, Still };

struct HeadAction {
  std::string origin;
  HeadKind kind = HeadKind::Nod;
  double at = 0.0;
  double end = 0.0;  // turn: kOpenEnd holds the pose; still: the window without noise
  double amplitude_deg = 0.0;
  int count = 1;      // nod, shake: how many times
  Direction target;   // turn, tilt (roll)
  double ramp = 0.4;  // turn, tilt: seconds to reach and to leave the pose
};

struct Storyboard {
  std::filesystem::path file;    // the storyboard script as given
  std::filesystem::path folder;  // its folder: relative names resolve here
  double fps = 25.0;
  bool fps_set = false;
  std::uint64_t seed = 1;
  bool seed_set = false;
  double duration = 0.0;         // at least this long (0: as long as its parts)
  std::filesystem::path output;  // storyboard.output, resolved; empty when absent
  std::vector<SpeechItem> speech;
  std::vector<ExpressionItem> expressions;
  std::vector<EyeAction> eyes;
  std::vector<HeadAction> head;
};

}  // namespace rostro::script
