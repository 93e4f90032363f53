#include "script/viseme_script.hpp"

#include <fmt/format.h>

#include <charconv>
#include <sstream>

#include "facecore/atomic_file.hpp"
#include "facecore/expression_library.hpp"

namespace rostro::script {
namespace {

const char* class_word(speech::PhonemeClass c) {
  switch (c) {
    case speech::PhonemeClass::Vowel:
      return "vowel";
    case speech::PhonemeClass::Consonant:
      return "consonant";
    case speech::PhonemeClass::Silence:
      break;
  }
  return "silence";
}

// A Lua string literal.
std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\')
      out += std::string("\\") + c;
    else if (c == '\n')
      out += "\\n";
    else
      out += c;
  }
  return out + "\"";
}

}  // namespace

VisemeScript viseme_script_for(const speech::PreparedSpeech& prepared,
                               const speech::AnimationOptions& options, const std::string& language,
                               const std::string& source, const std::filesystem::path& sound) {
  return {.source = source,
          .language = language,
          .fps = options.fps,
          .seed = options.seed,
          .duration_s = prepared.duration_s,
          .phonemes = prepared.resolution.phonemes,
          .emotions = prepared.emotions,
          .base_expression = options.base_expression,
          .base_intensity = options.base_intensity,
          .blinks = options.blinks,
          .saccades = options.saccades,
          .head_motion = options.head_motion,
          .sound = sound};
}

std::string exact_number(double value) {
  char buffer[64];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);
  (void)ec;  // 64 characters hold any double
  return std::string(buffer, end);
}

void write_viseme_script(std::ostream& out, const VisemeScript& s,
                         const std::filesystem::path& script_folder) {
  out << "-- Viseme script written by rostro speak (" << s.source << ").\n"
      << "-- `rostro script` runs it to the same FAP stream, frame for frame; edit it and run it\n"
      << "-- again. Each viseme: {start_s, end_s, viseme, class, word = N, phoneme = \"x\"}.\n"
      << "storyboard = {\n"
      << "  fps = " << exact_number(s.fps) << ",\n"
      << "  seed = " << s.seed << ",\n"
      << "  speech = {\n"
      << "    at = 0,\n"
      << "    duration = " << exact_number(s.duration_s) << ",\n";
  if (!s.language.empty()) out << "    lang = " << quoted(s.language) << ",\n";
  if (!s.sound.empty()) {
    const auto rel = std::filesystem::absolute(s.sound).lexically_relative(
        std::filesystem::absolute(script_folder));
    // The sandbox reads files inside the script's folder only.
    const bool outside = rel.empty() || *rel.begin() == "..";
    out << (outside ? "    -- (outside this folder: needs --allow-outside) sound = "
                    : "    sound = ")
        << quoted(rel.generic_string()) << ",\n";
  }
  if (s.base_expression != 0)
    out << "    emotion = {"
        << quoted(std::string(ExpressionLibrary::expression_name(s.base_expression))) << ", "
        << exact_number(s.base_intensity) << "},\n";
  if (!s.emotions.empty()) {
    out << "    emotions = {  -- {time_s, expression, intensity, ramp_s}\n";
    for (const auto& e : s.emotions)
      out << "      {" << exact_number(e.time_s) << ", "
          << quoted(std::string(ExpressionLibrary::expression_name(e.expression))) << ", "
          << exact_number(e.intensity) << ", " << exact_number(e.ramp_s) << "},\n";
    out << "    },\n";
  }
  out << "    visemes = {\n";
  for (const auto& p : s.phonemes) {
    out << "      {" << exact_number(p.start_s) << ", " << exact_number(p.end_s) << ", "
        << quoted(std::string(ExpressionLibrary::viseme_name(p.viseme))) << ", "
        << quoted(class_word(p.cls));
    if (p.word >= 0) out << ", word = " << p.word;
    out << ", phoneme = " << quoted(p.symbol);
    if (p.closes_lips) out << ", closes = true";
    out << "},\n";
  }
  out << "    },\n  },\n";
  out << "  eyes = {";
  if (s.blinks) out << " {\"blinks\"},";
  if (s.saccades) out << " {\"saccades\"},";
  out << " },\n";
  out << "  head = {" << (s.head_motion ? "" : " {\"still\"} ") << "},\n";
  out << "}\n";
}

void write_viseme_script(const std::filesystem::path& path, const VisemeScript& script) {
  std::ostringstream text;
  const auto folder = path.parent_path().empty() ? std::filesystem::path(".") : path.parent_path();
  write_viseme_script(text, script, folder);
  AtomicFile file(path);
  file.write(text.str());
  file.commit();
}

}  // namespace rostro::script
