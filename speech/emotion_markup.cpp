#include "speech/emotion_markup.hpp"

#include <cmath>
#include <map>
#include <sstream>

#include "facecore/error.hpp"

namespace rostro::speech {
namespace {

// Lower case ASCII and fold the accented Latin-1 letters Spanish and Portuguese use.
std::string fold(std::string_view s) {
  static const std::map<std::string, char> accents = {
      {"á", 'a'}, {"à", 'a'}, {"â", 'a'}, {"ã", 'a'}, {"é", 'e'}, {"ê", 'e'}, {"í", 'i'},
      {"ó", 'o'}, {"ô", 'o'}, {"õ", 'o'}, {"ú", 'u'}, {"ü", 'u'}, {"ñ", 'n'}, {"ç", 'c'},
      {"Á", 'a'}, {"À", 'a'}, {"Â", 'a'}, {"Ã", 'a'}, {"É", 'e'}, {"Ê", 'e'}, {"Í", 'i'},
      {"Ó", 'o'}, {"Ô", 'o'}, {"Õ", 'o'}, {"Ú", 'u'}, {"Ü", 'u'}, {"Ñ", 'n'}, {"Ç", 'c'}};
  std::string out;
  for (std::size_t i = 0; i < s.size();) {
    if (static_cast<unsigned char>(s[i]) >= 0x80 && i + 1 < s.size()) {
      if (auto it = accents.find(std::string(s.substr(i, 2))); it != accents.end()) {
        out.push_back(it->second);
        i += 2;
        continue;
      }
    }
    const char c = s[i++];
    if (c == ' ' || c == '-')
      out.push_back('_');
    else
      out.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
  }
  return out;
}

const std::map<std::string, int>& names() {
  static const std::map<std::string, int> table = {
      {"neutral", 0},   {"neutro", 0},  {"seriedad", 0},  {"serio", 0},
      {"fin", 0},       {"none", 0},    {"joy", 1},       {"happy", 1},
      {"happiness", 1}, {"reir", 1},    {"risa", 1},      {"feliz", 1},
      {"felicidad", 1}, {"alegria", 1}, {"carcajada", 1}, {"alegre", 1},
      {"smile", 1},     {"sadness", 2}, {"sad", 2},       {"tristeza", 2},
      {"triste", 2},    {"anger", 3},   {"angry", 3},     {"enojo", 3},
      {"enojado", 3},   {"ira", 3},     {"raiva", 3},     {"zangado", 3},
      {"fear", 4},      {"afraid", 4},  {"miedo", 4},     {"asustado", 4},
      {"medo", 4},      {"disgust", 5}, {"disgusto", 5},  {"reflejo_del_disgusto", 5},
      {"asco", 5},      {"nojo", 5},    {"surprise", 6},  {"surprised", 6},
      {"sorpresa", 6},  {"surpresa", 6}};
  return table;
}

std::size_t code_points(std::string_view s) {
  std::size_t n = 0;
  for (unsigned char c : s) n += (c & 0xC0) != 0x80;
  return n;
}

double parse_number(const std::string& text, bool& ok) {
  try {
    std::size_t used = 0;
    const double v = std::stod(text, &used);
    ok = used == text.size() && std::isfinite(v);
    return v;
  } catch (const std::exception&) {
    ok = false;
    return 0.0;
  }
}

}  // namespace

int emotion_from_name(std::string_view name) {
  const auto it = names().find(fold(name));
  return it == names().end() ? -1 : it->second;
}

std::string known_emotion_names() {
  return "neutral, joy, sadness, anger, fear, disgust, surprise (or Spanish/Portuguese names such "
         "as "
         "alegría, tristeza, enojo, miedo, disgusto, sorpresa, raiva, medo, nojo, surpresa)";
}

MarkedText parse_emotion_markup(std::string_view text, const std::string& name) {
  MarkedText out;
  std::size_t clean_cp = 0;  // code points written to `clean`
  const auto column = [&](std::size_t byte) { return code_points(text.substr(0, byte)) + 1; };
  const auto fail = [&](std::size_t byte, const std::string& what) {
    return InputError(name + ", column " + std::to_string(column(byte)) + ": " + what);
  };
  std::size_t i = 0;
  while (i < text.size()) {
    const char c = text[i];
    if (c == '{' && i + 1 < text.size() && text[i + 1] == '{') {
      out.clean.push_back('{');
      ++clean_cp;
      i += 2;
      continue;
    }
    const bool seed_tag = c == '<' && (fold(text.substr(i + 1, 4)) == "emo_" ||
                                       fold(text.substr(i + 1, 8)) == "emocion_");
    if (c == '{' || seed_tag) {
      const char close = c == '{' ? '}' : '>';
      const std::size_t end = text.find(close, i + 1);
      if (end == std::string_view::npos)
        throw fail(i, std::string("unclosed '") + c + "' (expected '" + close + "')");
      const std::string body(text.substr(i + 1, end - i - 1));
      EmotionTag tag;
      tag.position = clean_cp;
      tag.source = std::string(text.substr(i, end - i + 1));
      if (seed_tag) {
        const std::string word = body.substr(body.find('_') + 1);
        tag.expression = emotion_from_name(word);
        if (tag.expression < 0)
          throw fail(i, "'" + tag.source +
                            "' is not an emotion control word rostro knows (expected one of: " +
                            known_emotion_names() + ")");
      } else {
        std::istringstream words(body);
        std::string emotion;
        if (!(words >> emotion)) throw fail(i, "empty emotion tag '{}'");
        tag.expression = emotion_from_name(emotion);
        if (tag.expression < 0)
          throw fail(i, "unknown emotion '" + emotion +
                            "' (expected one of: " + known_emotion_names() + ")");
        std::string arg;
        bool have_intensity = false;
        while (words >> arg) {
          bool ok = false;
          if (arg.rfind("ramp=", 0) == 0) {
            std::string v = arg.substr(5);
            double scale = 1.0;
            if (v.size() > 2 && v.compare(v.size() - 2, 2, "ms") == 0) {
              v.resize(v.size() - 2);
              scale = 0.001;
            } else if (!v.empty() && v.back() == 's') {
              v.pop_back();
            }
            tag.ramp_s = parse_number(v, ok) * scale;
            if (!ok || tag.ramp_s < 0.0 || tag.ramp_s > 60.0)
              throw fail(i, "bad ramp '" + arg + "' in '" + tag.source +
                                "' (expected e.g. ramp=0.4s or ramp=400ms)");
          } else if (!have_intensity) {
            std::string v = arg;
            double scale = 1.0;
            if (!v.empty() && v.back() == '%') {
              v.pop_back();
              scale = 0.01;
            }
            tag.intensity = parse_number(v, ok) * scale;
            if (!ok || tag.intensity < 0.0 || tag.intensity > 1.0)
              throw fail(i, "bad intensity '" + arg + "' in '" + tag.source +
                                "' (expected 0..1 or 0%..100%)");
            have_intensity = true;
          } else {
            throw fail(i, "unexpected '" + arg + "' in '" + tag.source +
                              "' (expected {emotion [intensity] [ramp=T]})");
          }
        }
      }
      out.tags.push_back(std::move(tag));
      i = end + 1;
      continue;
    }
    if (c == '}' && i + 1 < text.size() && text[i + 1] == '}') {
      out.clean.push_back('}');
      ++clean_cp;
      i += 2;
      continue;
    }
    if (c == '}') throw fail(i, "'}' without an opening '{' (write '}}' for a literal brace)");
    out.clean.push_back(c);
    if ((static_cast<unsigned char>(c) & 0xC0) != 0x80) ++clean_cp;
    ++i;
  }
  return out;
}

}  // namespace rostro::speech
