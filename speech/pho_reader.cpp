#include "speech/pho_reader.hpp"

#include <fstream>
#include <sstream>

#include "facecore/error.hpp"

namespace rostro::speech {

std::vector<RawPhoneme> parse_pho(std::istream& in, const std::string& name) {
  std::vector<RawPhoneme> out;
  std::string line;
  long line_no = 0;
  double total_ms = 0.0;  // absolute running sum: no per-phoneme rounding
  while (std::getline(in, line)) {
    ++line_no;
    if (const auto c = line.find(';'); c != std::string::npos) line.erase(c);
    std::istringstream fields(line);
    std::string symbol;
    if (!(fields >> symbol)) continue;
    std::string dur_text;
    if (!(fields >> dur_text))
      throw InputError(
          where(name, line_no, "expected 'phoneme duration_ms', got only '" + symbol + "'"));
    double dur = 0.0;
    try {
      std::size_t used = 0;
      dur = std::stod(dur_text, &used);
      if (used != dur_text.size()) throw std::invalid_argument("trailing");
    } catch (const std::exception&) {
      throw InputError(
          where(name, line_no, "duration '" + dur_text + "' is not a number of milliseconds"));
    }
    if (!(dur >= 0.0) || dur > 60000.0)
      throw InputError(
          where(name, line_no, "duration " + dur_text + " ms is out of range (0..60000)"));
    double value = 0.0;
    int count = 0;
    while (fields >> value) ++count;
    if (!fields.eof() || count % 2 != 0)
      throw InputError(
          where(name, line_no, "pitch targets must be pairs of numbers (position% pitch_hz)"));
    RawPhoneme p;
    p.symbol = symbol;
    p.start_s = total_ms / 1000.0;
    total_ms += dur;
    p.end_s = total_ms / 1000.0;
    out.push_back(std::move(p));
  }
  if (out.empty()) throw InputError(where(name, 0, "no phonemes in the .pho file"));
  return out;
}

std::vector<RawPhoneme> read_pho(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(where(path.string(), 0, "cannot open the .pho file"));
  return parse_pho(in, path.string());
}

}  // namespace rostro::speech
