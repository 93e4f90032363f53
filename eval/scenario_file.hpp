#pragma once
// The shape both scenario files share (data/eval/suite.json, data/eval/closed_loop.json): a
// JSON object with a non-empty "scenarios" array of uniquely named scenarios, whose top-level
// keys listed by the caller are defaults for every scenario. Included by the two readers only.

#include <filesystem>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "facecore/error.hpp"

namespace rostro::eval {

// `parse(scenario, defaults, where)` reads one scenario; `where` names the file and the
// scenario's place for its errors. Throws InputError naming the file (and scenario) at fault.
template <typename Scenario, typename Parse>
std::vector<Scenario> parse_scenario_list(const nlohmann::json& j,
                                          const std::filesystem::path& path,
                                          std::initializer_list<const char*> default_keys,
                                          Parse parse) {
  if (!j.is_object() || !j.contains("scenarios") || !j["scenarios"].is_array() ||
      j["scenarios"].empty())
    throw InputError(path.string() + ": expected an object with a non-empty 'scenarios' array");
  nlohmann::json defaults = nlohmann::json::object();
  for (const char* key : default_keys)
    if (j.contains(key)) defaults[key] = j[key];
  std::vector<Scenario> scenarios;
  std::set<std::string> names;
  for (std::size_t i = 0; i < j["scenarios"].size(); ++i) {
    const std::string where = path.string() + ": scenario " + std::to_string(i + 1);
    try {
      scenarios.push_back(parse(j["scenarios"][i], defaults, where));
    } catch (const nlohmann::json::exception& e) {
      throw InputError(where + ": " + e.what());
    }
    if (!names.insert(scenarios.back().name).second)
      throw InputError(where + ": the name '" + scenarios.back().name + "' repeats");
  }
  return scenarios;
}

}  // namespace rostro::eval
