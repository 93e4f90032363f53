#pragma once
// Emotion markup in the text given to `rostro speak` (docs/speech.md):
//   {joy}  {joy 0.6}  {joy 60%}  {sadness 0.8 ramp=0.5s}  {neutral ramp=800ms}
// and the seed's control words (seed000 Table 6.1) such as <Emo_Reír>, <Emo_Tristeza>,
// <Emo_NEUTRAL>. A tag applies from the end of the word before it. "{{" is a literal '{'.

#include <string>
#include <string_view>
#include <vector>

namespace rostro::speech {

struct EmotionTag {
  std::size_t position = 0;  // code-point index in the clean text where the tag stood
  int expression = 0;        // MPEG-4 expression_select: 0 neutral, 1 joy .. 6 surprise
  double intensity = 1.0;    // 0..1
  double ramp_s = -1.0;      // seconds to reach it; < 0: the default ramp
  std::string source;        // the tag as written, for messages
};

struct MarkedText {
  std::string clean;  // the text to speak, tags removed
  std::vector<EmotionTag> tags;
};

// Throws InputError "<name>, column N: what" for an unknown emotion, a bad intensity or
// ramp, or an unclosed tag. Columns count code points from 1.
MarkedText parse_emotion_markup(std::string_view text, const std::string& name = "text");

// 0..6 for an emotion name or alias (English, Spanish, Portuguese, seed control words;
// case and accents ignored); -1 when unknown.
int emotion_from_name(std::string_view name);
std::string known_emotion_names();

}  // namespace rostro::speech
