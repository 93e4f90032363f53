#include "speech/mouth_cues.hpp"

#include <fmt/format.h>

#include <cmath>

#include "facecore/atomic_file.hpp"
#include "facecore/error.hpp"

namespace rostro::speech {
namespace {

constexpr double kStep = 0.01;  // Rhubarb times are centiseconds

long to_steps(double t) {
  return std::lround(t / kStep);
}

double at_step(long steps) {
  return static_cast<double>(steps) * kStep;
}

std::string seconds(long steps) {
  return fmt::format("{:.2f}", at_step(steps));
}

std::string escaped_json(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    if (static_cast<unsigned char>(c) < 0x20) {
      out += fmt::format("\\u{:04x}", static_cast<int>(c));
      continue;
    }
    out += c;
  }
  return out;
}

std::string escaped_xml(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

}  // namespace

char mouth_shape(const Phoneme& phoneme) {
  if (phoneme.cls == PhonemeClass::Silence) return 'X';
  switch (phoneme.viseme) {
    case 1:
      return 'A';
    case 2:
      return 'G';
    case 8:
      return !phoneme.symbol.empty() && (phoneme.symbol[0] == 'l' || phoneme.symbol[0] == 'L')
                 ? 'H'
                 : 'B';
    case 10:
      return 'D';
    case 11:
      return 'C';
    case 13:
      return 'E';
    case 14:
      return 'F';
    case 0:
      return 'X';
    default:
      return 'B';  // 3-7, 9 consonants with teeth together, 12 (ee)
  }
}

std::vector<MouthCue> mouth_cues(const std::vector<Phoneme>& phonemes, double duration_s) {
  const long end = std::max(1L, to_steps(duration_s));
  std::vector<MouthCue> cues;
  long at = 0;  // where the next cue starts, in steps
  auto add = [&](char shape, long until) {
    until = std::min(until, end);
    if (until <= at) return;
    if (!cues.empty() && cues.back().shape == shape) {
      cues.back().end_s = at_step(until);
    } else {
      cues.push_back({at_step(at), at_step(until), shape});
    }
    at = until;
  };
  for (const Phoneme& p : phonemes) {
    // A phoneme shorter than a step still shows if it closes the lips (A): it takes the
    // step it falls in, as a bilabial must be seen.
    long until = to_steps(p.end_s);
    if (until <= at && mouth_shape(p) == 'A' && at < end) until = at + 1;
    add(mouth_shape(p), until);
  }
  add('X', end);
  return cues;
}

CueFormat cue_format_for(const std::filesystem::path& path) {
  const std::string ext = path.extension().string();
  if (ext == ".tsv") return CueFormat::Tsv;
  if (ext == ".json") return CueFormat::Json;
  if (ext == ".xml") return CueFormat::Xml;
  if (ext == ".dat") return CueFormat::Dat;
  throw InputError(path.string() + ": unknown mouth-cue format '" + ext +
                   "' (expected .tsv, .json, .xml or .dat)");
}

std::string format_cues(const std::vector<MouthCue>& cues, CueFormat format,
                        const std::string& sound_file, double duration_s, double dat_fps) {
  std::string out;
  const long total = to_steps(duration_s);
  switch (format) {
    case CueFormat::Tsv:
      // One line per cue start; the last line is the end, resting (Rhubarb's layout).
      for (const MouthCue& c : cues)
        out += fmt::format("{}\t{}\n", seconds(to_steps(c.start_s)), c.shape);
      out += fmt::format("{}\tX\n", seconds(cues.empty() ? total : to_steps(cues.back().end_s)));
      break;
    case CueFormat::Json:
      out += "{\n  \"metadata\": {\n";
      out += fmt::format("    \"soundFile\": \"{}\",\n    \"duration\": {}\n",
                         escaped_json(sound_file), seconds(total));
      out += "  },\n  \"mouthCues\": [\n";
      for (std::size_t k = 0; k < cues.size(); ++k)
        out += fmt::format("    {{ \"start\": {}, \"end\": {}, \"value\": \"{}\" }}{}\n",
                           seconds(to_steps(cues[k].start_s)), seconds(to_steps(cues[k].end_s)),
                           cues[k].shape, k + 1 < cues.size() ? "," : "");
      out += "  ]\n}\n";
      break;
    case CueFormat::Xml:
      out += "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<rhubarbResult>\n  <metadata>\n";
      out += fmt::format("    <soundFile>{}</soundFile>\n    <duration>{}</duration>\n",
                         escaped_xml(sound_file), seconds(total));
      out += "  </metadata>\n  <mouthCues>\n";
      for (const MouthCue& c : cues)
        out += fmt::format("    <mouthCue start=\"{}\" end=\"{}\">{}</mouthCue>\n",
                           seconds(to_steps(c.start_s)), seconds(to_steps(c.end_s)), c.shape);
      out += "  </mouthCues>\n</rhubarbResult>\n";
      break;
    case CueFormat::Dat: {
      // Moho switch data: 1-based frame numbers; a cue starting in the frame of the
      // previous one is dropped, as Rhubarb does.
      out += "MohoSwitch1\n";
      auto frame = [&](double t) { return 1 + static_cast<long>(dat_fps * t + 1e-9); };
      long last = 0;
      for (const MouthCue& c : cues) {
        const long f = frame(c.start_s);
        if (f == last) continue;
        out += fmt::format("{} {}\n", f, c.shape);
        last = f;
      }
      long f = frame(cues.empty() ? duration_s : cues.back().end_s);
      if (f == last) ++f;
      out += fmt::format("{} X\n", f);
      break;
    }
  }
  return out;
}

void write_cues(const std::filesystem::path& path, const std::vector<MouthCue>& cues,
                const std::string& sound_file, double duration_s, double dat_fps) {
  const CueFormat format = cue_format_for(path);
  AtomicFile file(path);
  file.write(format_cues(cues, format, sound_file, duration_s, dat_fps));
  file.commit();
}

}  // namespace rostro::speech
