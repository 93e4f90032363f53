#pragma once
// The geometric model the fit inverts: each marker's 3D neutral position (head frame, mm)
// and the FAPs that move it, each as a step in mm per FAP unit (fap_axis() x actor FAPU).

#include <Eigen/Core>
#include <set>
#include <string>
#include <vector>

#include "calib/actor_profile.hpp"
#include "facecore/feature_point.hpp"
#include "mapping/hierarchy.hpp"

namespace rostro::mapping {

struct FapStep {
  int fap = 0;           // FAP id
  Eigen::Vector3d step;  // head-frame displacement (mm) of one unit of this FAP
};

struct ModelMarker {
  std::string marker;
  FeaturePointId feature_point;
  Eigen::Vector3d neutral;    // head frame, mm
  std::vector<FapStep> faps;  // empty for a rigid marker (eye corner, forehead tag)
};

struct MarkerModelOptions {
  // FAPs along z (thrust_jaw, push_b_lip, ...) are barely visible to one camera and are left
  // to the hierarchy unless asked for.
  bool fit_depth_faps = false;
  std::set<int> excluded_faps;  // never fitted (their markers still constrain the pose)
  // The hierarchy's rules that will derive unfitted FAPs from fitted ones (inner lip = outer
  // lip, thrust_jaw = 0.5 x open_jaw, ...). With a profile's marker motion, a fitted FAP's
  // step also carries the motion of the FAPs derived from it, so the fit explains the markers
  // with the same face the hierarchy will write.
  std::vector<HierarchyRule> derived_rules;
};

struct MarkerModel {
  std::vector<ModelMarker> markers;
  std::vector<int> faps;  // every fitted FAP id, ascending
};

// The translating FAPs (non-zero fap_axis) that move feature point `fp`.
std::vector<int> faps_moving(FeaturePointId fp, bool include_depth);

// Markers of the profile that have a 3D position. Throws InputError when none has.
MarkerModel build_marker_model(const calib::ActorProfile& profile,
                               const MarkerModelOptions& options = {});

}  // namespace rostro::mapping
