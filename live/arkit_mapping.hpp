#pragma once
// FAPs to the 52 ARKit blend shapes that VMC receivers (VSeeFace "perfect sync", Warudo)
// animate avatars with. The table lives in data/live/arkit.json: each blend shape is a sum
// of FAP terms, value = clamp(sum(fap / full_scale), 0, 1), where full_scale is the FAP
// value (signed) that alone drives the shape fully.

#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "facecore/fap_frame.hpp"

namespace rostro::live {

inline constexpr int kArkitShapeCount = 52;

struct BlendShapeTerm {
  int fap = 0;
  double full_scale = 1.0;
};

struct BlendShapeRule {
  std::string name;
  std::vector<BlendShapeTerm> terms;  // empty: the shape is sent at 0 (nothing drives it)
};

class ArkitMapping {
 public:
  // Throws InputError for malformed JSON, an unknown FAP or blend shape name, a zero scale,
  // or a table that does not name all 52 shapes exactly once.
  static ArkitMapping load(const std::filesystem::path& path);
  static ArkitMapping load_default();  // data/live/arkit.json

  const std::vector<BlendShapeRule>& rules() const { return rules_; }
  // One weight per rule, in rules() order, each in 0..1.
  void evaluate(const FapFrame& frame, std::vector<float>& weights) const;

 private:
  std::vector<BlendShapeRule> rules_;
};

// The 52 ARKit names in Apple's order.
const std::array<const char*, kArkitShapeCount>& arkit_shape_names();

// Apple's camelCase name ("eyeBlinkLeft") as the PascalCase "perfect sync" clip name VRM
// avatars and Live Link Face use ("EyeBlinkLeft").
std::string pascal_case(const std::string& arkit_name);

}  // namespace rostro::live
