#include "render/fap_assignments.hpp"

#include <cmath>
#include <string>

#include "facecore/error.hpp"
#include "facecore/fap_table.hpp"

namespace rostro::render {
namespace {

std::string trim(std::string_view s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string_view::npos) return {};
  const auto e = s.find_last_not_of(" \t");
  return std::string(s.substr(b, e - b + 1));
}

int fap_id_of(const std::string& key, const std::string& item) {
  if (!key.empty() && key.find_first_not_of("0123456789") == std::string::npos) {
    const int id = key.size() > 3 ? 0 : std::stoi(key);
    if (!is_fap_id(id)) {
      throw InputError("pose '" + item + "': FAP " + key + " does not exist (ids are 1..68)");
    }
    return id;
  }
  if (const auto id = find_fap(key)) return *id;
  throw InputError("pose '" + item + "': unknown FAP '" + key +
                   "' (use an id 3..68 or a name such as open_jaw)");
}

}  // namespace

FapFrame parse_fap_assignments(std::string_view text) {
  FapFrame frame;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    const std::string item = trim(text.substr(start, comma - start));
    start = comma + 1;
    if (item.empty()) {
      if (comma >= text.size()) break;
      continue;
    }
    const auto equals = item.find('=');
    if (equals == std::string::npos) {
      throw InputError("pose '" + item + "': expected FAP=VALUE, e.g. 3=400 or open_jaw=400");
    }
    const std::string key = trim(std::string_view(item).substr(0, equals));
    const std::string value_text = trim(std::string_view(item).substr(equals + 1));
    const int id = fap_id_of(key, item);
    if (id == kVisemeFap || id == kExpressionFap) {
      throw InputError("pose '" + item +
                       "': FAPs 1 and 2 are high-level; use --viseme or --expression");
    }
    double value = 0.0;
    std::size_t used = 0;
    try {
      value = std::stod(value_text, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (value_text.empty() || used != value_text.size() || !std::isfinite(value)) {
      throw InputError("pose '" + item + "': '" + value_text + "' is not a number");
    }
    if (frame.has(id)) throw InputError("pose '" + item + "': FAP " + key + " is given twice");
    frame.set(id, value);
  }
  return frame;
}

}  // namespace rostro::render
