#include "mapping/hierarchy.hpp"

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "facecore/data_path.hpp"
#include "facecore/error.hpp"

namespace rostro::mapping {
namespace {

std::size_t bit(int id) {
  return static_cast<std::size_t>(id - 1);
}

}  // namespace

std::optional<int> mirror_fap(int id) {
  const std::string name(fap_info(id).name);
  std::string twin;
  std::size_t start = 0;
  bool swapped = false;
  while (start <= name.size()) {
    std::size_t end = name.find('_', start);
    if (end == std::string::npos) end = name.size();
    std::string token = name.substr(start, end - start);
    if (token == "l")
      token = "r", swapped = true;
    else if (token == "r")
      token = "l", swapped = true;
    else if (token == "lm")
      token = "rm", swapped = true;
    else if (token == "rm")
      token = "lm", swapped = true;
    twin += (twin.empty() && start == 0 ? "" : "_") + token;
    start = end + 1;
  }
  if (!swapped) return std::nullopt;
  return find_fap(twin);
}

Hierarchy hierarchy_from_json(const std::string& text, const std::string& context) {
  using nlohmann::json;
  json j;
  try {
    j = json::parse(text);
  } catch (const json::exception& e) {  // parse_error, or out_of_range for a number
    throw InputError(context + ": not valid JSON (" + e.what() + ")");
  }
  if (!j.is_object() || !j.contains("rules") || !j["rules"].is_array())
    throw InputError(context + ": expected an object with a 'rules' array");
  Hierarchy h;
  if (j.contains("mirror_missing")) {
    if (!j["mirror_missing"].is_boolean())
      throw InputError(context + ": 'mirror_missing' must be true or false");
    h.mirror_missing = j["mirror_missing"].get<bool>();
  }
  const json& rules = j["rules"];
  for (std::size_t i = 0; i < rules.size(); ++i) {
    const std::string where = context + ": rule " + std::to_string(i + 1);
    const json& r = rules[i];
    if (!r.is_object()) throw InputError(where + ": expected an object");
    auto fap = [&](const char* key) {
      if (!r.contains(key) || !r[key].is_string())
        throw InputError(where + ": '" + key + "' must be a FAP name");
      const std::string name = r[key].get<std::string>();
      auto id = find_fap(name);
      if (!id) throw InputError(where + ": '" + name + "' is not an MPEG-4 FAP name");
      if (*id <= kExpressionFap)
        throw InputError(where + ": '" + name + "' is a high-level FAP; rules take low-level ones");
      return *id;
    };
    HierarchyRule rule;
    rule.target = fap("target");
    rule.source = fap("source");
    if (rule.target == rule.source) throw InputError(where + ": a FAP cannot derive itself");
    if (!r.contains("factor") || !r["factor"].is_number())
      throw InputError(where + ": 'factor' must be a number");
    rule.factor = r["factor"].get<double>();
    if (r.contains("mirror_fallback")) {
      if (!r["mirror_fallback"].is_boolean())
        throw InputError(where + ": 'mirror_fallback' must be true or false");
      rule.mirror_fallback = r["mirror_fallback"].get<bool>();
    }
    if (r.contains("why") && r["why"].is_string()) rule.why = r["why"].get<std::string>();
    h.rules.push_back(std::move(rule));
  }
  return h;
}

Hierarchy read_hierarchy(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path.string() + ": cannot open the hierarchy rules");
  std::stringstream text;
  text << in.rdbuf();
  return hierarchy_from_json(text.str(), path.string());
}

Hierarchy default_hierarchy() {
  return read_hierarchy(data_file("hierarchy.json"));
}

std::bitset<kFapCount> apply_hierarchy(const Hierarchy& h, const Fapu& fapu, FapFrame& frame) {
  std::bitset<kFapCount> derived;
  const FapFrame measured = frame;
  auto set = [&](int id, double value) {
    if (!fap_info(id).bidirectional && value < 0) value = 0;
    frame.set(id, value);
    derived.set(bit(id));
  };

  if (h.mirror_missing) {
    for (int id = kExpressionFap + 1; id <= kFapCount; ++id) {
      if (measured.has(id)) continue;
      auto twin = mirror_fap(id);
      if (twin && measured.has(*twin)) set(id, measured.get(*twin));
    }
  }
  for (const HierarchyRule& rule : h.rules) {
    if (frame.has(rule.target)) continue;  // never overwrite measured or earlier results
    int source = rule.source;
    if (!frame.has(source)) {
      auto twin = rule.mirror_fallback ? mirror_fap(source) : std::nullopt;
      if (!twin || !frame.has(*twin)) continue;
      source = *twin;
    }
    const double value =
        fapu.convert(frame.get(source), fap_info(source).unit, fap_info(rule.target).unit);
    set(rule.target, rule.factor * value);
  }
  return derived;
}

}  // namespace rostro::mapping
