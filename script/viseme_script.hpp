#pragma once
// The generated viseme script (seed004 6.2): what `rostro speak --viseme-script` derived from
// the text, as a storyboard that `rostro script` runs to the same FAP stream, frame for frame.
// It holds the timed visemes (with their phoneme, class and word, which the coarticulation
// planner needs), the emotion events, the clip's length, the frame rate and seed, and the eye
// and head behaviour `rostro speak` added. Times are written in the shortest form that reads
// back to the same double, so nothing drifts; a user may edit it and run it again.

#include <cstdint>
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "speech/animator.hpp"
#include "speech/phoneme.hpp"
#include "speech/pipeline.hpp"

namespace rostro::script {

struct VisemeScript {
  std::string source;  // what it was made from, for the header comment
  std::string language;
  double fps = 25.0;
  std::uint64_t seed = 1;
  double duration_s = 0.0;
  std::vector<speech::Phoneme> phonemes;
  std::vector<speech::EmotionEvent> emotions;
  int base_expression = 0;
  double base_intensity = 1.0;
  bool blinks = true, saccades = true, head_motion = true;
  std::filesystem::path sound;  // written relative to the script; empty: none
};

// What `rostro speak` animated: the prepared speech, the options it animated with, the
// language it spoke and the WAV it wrote (empty: none).
VisemeScript viseme_script_for(const speech::PreparedSpeech& prepared,
                               const speech::AnimationOptions& options, const std::string& language,
                               const std::string& source, const std::filesystem::path& sound);

void write_viseme_script(std::ostream& out, const VisemeScript& script,
                         const std::filesystem::path& script_folder);
// Through a temporary file (never half a file). Throws InputError on a write failure.
void write_viseme_script(const std::filesystem::path& path, const VisemeScript& script);

// The shortest decimal text that reads back as exactly `value`.
std::string exact_number(double value);

}  // namespace rostro::script
