#include "mapping/marker_model.hpp"

#include <algorithm>
#include <sstream>

#include "facecore/error.hpp"
#include "facecore/fap_table.hpp"

namespace rostro::mapping {

std::vector<int> faps_moving(FeaturePointId fp, bool include_depth) {
  std::vector<int> out;
  const std::string name = fp.str();
  for (const FapInfo& fap : fap_table()) {
    if (fap.feature_point != name) continue;
    const auto axis = fap_axis(fap);
    if (axis[0] == 0 && axis[1] == 0 && (axis[2] == 0 || !include_depth)) continue;
    out.push_back(fap.id);
  }
  return out;
}

namespace {

// Motion per unit of each FAP with the rules' targets folded into their sources: a rule
// target = factor x source (converted through the FAPU) moves the marker by factor x the
// target's motion per source unit, since motion is in multiples of each FAP's own FAPU. Rules
// go in reverse file order, so a target that a later rule uses as a source is folded first.
calib::FapMotion fold_derived(calib::FapMotion motion, const std::set<int>& fitted,
                              const std::vector<HierarchyRule>& rules) {
  for (auto rule = rules.rbegin(); rule != rules.rend(); ++rule) {
    if (fitted.count(rule->target)) continue;  // measured: the rule never overwrites it
    // A depth-only target (thrust_jaw = 0.5 x open_jaw) is a guess one camera cannot check;
    // folding it in would bend the visible FAPs toward the guess.
    const auto axis = fap_axis(fap_info(rule->target));
    if (axis[0] == 0 && axis[1] == 0) continue;
    auto t = motion.find(rule->target);
    if (t == motion.end()) continue;
    const Eigen::Vector3d add = rule->factor * t->second;
    auto& s = motion.try_emplace(rule->source, Eigen::Vector3d::Zero()).first->second;
    s += add;
  }
  return motion;
}

}  // namespace

MarkerModel build_marker_model(const calib::ActorProfile& profile,
                               const MarkerModelOptions& options) {
  // The fitted FAPs: those of the points that carry (non-rigid) markers.
  std::set<int> faps;
  for (const calib::NeutralMarker& m : profile.markers) {
    if (!m.position || m.rigid) continue;
    for (int id : faps_moving(m.feature_point, options.fit_depth_faps))
      if (!options.excluded_faps.count(id)) faps.insert(id);
  }
  MarkerModel model;
  for (const calib::NeutralMarker& m : profile.markers) {
    if (!m.position) continue;
    ModelMarker mm{m.marker, m.feature_point, *m.position, {}};
    const auto found = profile.marker_motion.find(m.marker);
    calib::FapMotion folded;
    if (found != profile.marker_motion.end())
      folded = fold_derived(found->second, faps, options.derived_rules);
    const calib::FapMotion* motion = found == profile.marker_motion.end() ? nullptr : &folded;
    if (!m.rigid) {
      for (int id : faps) {
        const FapInfo& info = fap_info(id);
        const double unit = profile.fapu.unit_size(info.unit);
        Eigen::Vector3d step = Eigen::Vector3d::Zero();
        if (motion) {
          // The head's own deformation at the marker: every fitted FAP that moves it, so a
          // lower-lip marker carried by open_jaw is not read as a lip FAP.
          if (auto it = motion->find(id); it != motion->end()) step = it->second * unit;
        } else if (info.feature_point == m.feature_point.str()) {
          const auto axis = fap_axis(info);
          step = Eigen::Vector3d(axis[0], axis[1], axis[2]) * unit;
        }
        if (step.squaredNorm() > 0) mm.faps.push_back({id, step});
      }
    }
    model.markers.push_back(std::move(mm));
  }
  if (model.markers.empty())
    throw InputError("actor profile '" + profile.name +
                     "': no marker has a 3D neutral position (recalibrate the actor)");
  model.faps.assign(faps.begin(), faps.end());
  return model;
}

}  // namespace rostro::mapping
