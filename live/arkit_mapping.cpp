#include "live/arkit_mapping.hpp"

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "facecore/data_path.hpp"
#include "facecore/error.hpp"
#include "facecore/fap_table.hpp"
#include "facecore/json_file.hpp"

namespace rostro::live {

const std::array<const char*, kArkitShapeCount>& arkit_shape_names() {
  static const std::array<const char*, kArkitShapeCount> names = {
      "eyeBlinkLeft",      "eyeLookDownLeft",    "eyeLookInLeft",
      "eyeLookOutLeft",    "eyeLookUpLeft",      "eyeSquintLeft",
      "eyeWideLeft",       "eyeBlinkRight",      "eyeLookDownRight",
      "eyeLookInRight",    "eyeLookOutRight",    "eyeLookUpRight",
      "eyeSquintRight",    "eyeWideRight",       "jawForward",
      "jawLeft",           "jawRight",           "jawOpen",
      "mouthClose",        "mouthFunnel",        "mouthPucker",
      "mouthLeft",         "mouthRight",         "mouthSmileLeft",
      "mouthSmileRight",   "mouthFrownLeft",     "mouthFrownRight",
      "mouthDimpleLeft",   "mouthDimpleRight",   "mouthStretchLeft",
      "mouthStretchRight", "mouthRollLower",     "mouthRollUpper",
      "mouthShrugLower",   "mouthShrugUpper",    "mouthPressLeft",
      "mouthPressRight",   "mouthLowerDownLeft", "mouthLowerDownRight",
      "mouthUpperUpLeft",  "mouthUpperUpRight",  "browDownLeft",
      "browDownRight",     "browInnerUp",        "browOuterUpLeft",
      "browOuterUpRight",  "cheekPuff",          "cheekSquintLeft",
      "cheekSquintRight",  "noseSneerLeft",      "noseSneerRight",
      "tongueOut"};
  return names;
}

std::string pascal_case(const std::string& arkit_name) {
  std::string name = arkit_name;
  if (!name.empty() && name[0] >= 'a' && name[0] <= 'z') name[0] = static_cast<char>(name[0] - 32);
  return name;
}

ArkitMapping ArkitMapping::load(const std::filesystem::path& path) {
  const std::string file = path.string();
  const nlohmann::json doc = read_json_file(path, "the ARKit mapping");
  const std::set<std::string> known(arkit_shape_names().begin(), arkit_shape_names().end());
  std::set<std::string> seen;
  ArkitMapping mapping;
  try {
    for (const auto& [name, terms] : doc.at("blendshapes").items()) {
      if (!known.count(name))
        throw InputError(file + ": '" + name + "' is not an ARKit blend shape");
      if (!seen.insert(name).second) throw InputError(file + ": '" + name + "' appears twice");
      BlendShapeRule rule{name, {}};
      for (const auto& [fap_name, scale] : terms.items()) {
        const auto id = find_fap(fap_name);
        if (!id || *id <= kExpressionFap)
          throw InputError(file + ": " + name + ": unknown low-level FAP '" + fap_name + "'");
        const double full_scale = scale.get<double>();
        if (full_scale == 0.0)
          throw InputError(file + ": " + name + ": " + fap_name + " has scale 0");
        rule.terms.push_back({*id, full_scale});
      }
      mapping.rules_.push_back(std::move(rule));
    }
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file + ": " + e.what());
  }
  if (seen.size() != known.size())
    throw InputError(file + ": names " + std::to_string(seen.size()) +
                     " blend shapes, expected all 52");
  return mapping;
}

ArkitMapping ArkitMapping::load_default() {
  return load(data_file("live/arkit.json"));
}

void ArkitMapping::evaluate(const FapFrame& frame, std::vector<float>& weights) const {
  weights.resize(rules_.size());
  for (std::size_t i = 0; i < rules_.size(); ++i) {
    double sum = 0;
    for (const BlendShapeTerm& t : rules_[i].terms) sum += frame.get(t.fap) / t.full_scale;
    weights[i] = static_cast<float>(std::clamp(sum, 0.0, 1.0));
  }
}

}  // namespace rostro::live
