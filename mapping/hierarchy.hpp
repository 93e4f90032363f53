#pragma once
// The FAP relationship hierarchy (seed section 4.3.3): FAPs that no marker measures are
// derived from measured ones, FAP_N = c x FAP_R (Eq. 4.17), by rules read from
// data/hierarchy.json. Order: measured FAPs; mirror fill (a FAP whose left/right twin was
// measured and which was not); the rules in file order, so a rule may use what an earlier
// rule derived. A rule never overwrites a FAP that is already set. When source and target
// use different units the source is converted through the actor FAPU first, so c is a ratio
// of physical displacements.

#include <bitset>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "facecore/fap_frame.hpp"
#include "facecore/fapu.hpp"

namespace rostro::mapping {

struct HierarchyRule {
  int target = 0;
  int source = 0;
  double factor = 1.0;
  bool mirror_fallback = true;  // source missing: use its left/right twin
  std::string why;
};

struct Hierarchy {
  bool mirror_missing = true;  // fill a FAP from its measured twin
  std::vector<HierarchyRule> rules;
};

// The left/right twin of a FAP ("raise_l_i_eyebrow" <-> "raise_r_i_eyebrow"); nullopt for
// FAPs on the mid-line. Twins take equal values for a symmetric expression.
std::optional<int> mirror_fap(int id);

// Throws InputError naming the file, the rule and what is wrong.
Hierarchy read_hierarchy(const std::filesystem::path& path);
Hierarchy hierarchy_from_json(const std::string& text, const std::string& context);
// data/hierarchy.json.
Hierarchy default_hierarchy();

// Adds the derived FAPs to `frame`; returns which FAPs it set.
std::bitset<kFapCount> apply_hierarchy(const Hierarchy& hierarchy, const Fapu& fapu,
                                       FapFrame& frame);

}  // namespace rostro::mapping
