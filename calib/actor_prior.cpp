#include "calib/actor_prior.hpp"

#include <iterator>
#include <optional>
#include <vector>

#include "calib/generic_face.hpp"
#include "facecore/deformer.hpp"
#include "facecore/error.hpp"
#include "facecore/face_model.hpp"
#include "facecore/fap_table.hpp"

namespace rostro::calib {

std::map<FeaturePointId, std::map<int, Eigen::Vector3d>> feature_point_motion(
    const FaceModel& model) {
  std::map<int, FeaturePointId> at_vertex;
  for (const auto& [fp, v] : model.feature_points) at_vertex[v] = fp;
  const Eigen::SparseMatrix<double> map = Deformer(model).linear_map();  // 3V x 68
  std::map<FeaturePointId, std::map<int, Eigen::Vector3d>> out;
  for (int col = 0; col < map.outerSize(); ++col) {
    const int id = col + 1;
    // Head rotation (48-50) is the pose; eyeball turns (23-26) are rotations, not linear.
    if (id < 3 || (id >= 23 && id <= 26) || (id >= 48 && id <= 50)) continue;
    const double unit = model.fapu.unit_size(fap_info(id).unit);
    if (!(unit > 0)) continue;
    for (Eigen::SparseMatrix<double>::InnerIterator it(map, col); it; ++it) {
      const auto row = static_cast<int>(it.row());
      auto fp = at_vertex.find(row / 3);
      if (fp == at_vertex.end()) continue;
      auto& step = out[fp->second].try_emplace(id, Eigen::Vector3d::Zero()).first->second;
      step[row % 3] += it.value() / unit;
    }
  }
  // Drop the negligible couplings (under 1 % of a FAPU per FAPU).
  for (auto& [fp, faps] : out)
    for (auto it = faps.begin(); it != faps.end();)
      it = it->second.norm() < 0.01 ? faps.erase(it) : std::next(it);
  return out;
}

ActorPrior load_actor_prior() {
  try {
    const FaceModel head = load_default_face_model();
    return {head.feature_point_positions(), "the default head (" + head.name + ")",
            feature_point_motion(head)};
  } catch (const InputError&) {
    return {generic_face_points(), "rostro's built-in generic face", {}};
  }
}

ActorCalibrationOptions actor_calibration_options(const tracking::MarkerLayout& layout,
                                                  const ActorPrior& prior,
                                                  const std::string& name) {
  ActorCalibrationOptions o;
  o.name = name;
  o.prior = &prior.points;
  o.prior_name = prior.name;
  if (!prior.motion.empty()) o.motion = &prior.motion;
  std::vector<NominalMarker> nominal;
  for (const auto& m : layout.markers) {
    std::optional<FeaturePointId> fp;
    if (is_feature_point(m.feature_point)) fp = m.feature_point;
    nominal.push_back({m.id, fp, {m.position_mm.x, m.position_mm.y, m.position_mm.z}});
    if (m.rigid) o.rigid_markers.insert(m.id);
  }
  o.marker_priors = place_nominal_markers(nominal, prior.points);
  return o;
}

}  // namespace rostro::calib
