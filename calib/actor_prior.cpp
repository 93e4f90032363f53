#include "calib/actor_prior.hpp"

#include <Eigen/Geometry>
#include <iterator>
#include <limits>
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

std::vector<Eigen::Vector3d> front_skin(const FaceModel& model) {
  std::vector<Eigen::Vector3d> normals(model.positions.size(), Eigen::Vector3d::Zero());
  for (const Eigen::Vector3i& t : model.triangles) {
    const auto a = static_cast<std::size_t>(t.x()), b = static_cast<std::size_t>(t.y()),
               c = static_cast<std::size_t>(t.z());
    const Eigen::Vector3d pa = model.positions[a].cast<double>();
    const Eigen::Vector3d f =
        (model.positions[b].cast<double>() - pa).cross(model.positions[c].cast<double>() - pa);
    normals[a] += f, normals[b] += f, normals[c] += f;
  }
  std::vector<Eigen::Vector3d> out;
  for (std::size_t i = 0; i < normals.size(); ++i)
    if (normals[i].z() > 0) out.push_back(model.positions[i].cast<double>());
  return out;
}

ActorPrior load_actor_prior() {
  try {
    const FaceModel head = load_default_face_model();
    return {head.feature_point_positions(), "the default head (" + head.name + ")",
            feature_point_motion(head), front_skin(head)};
  } catch (const InputError&) {
    return {generic_face_points(), "rostro's built-in generic face", {}, {}};
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
    const bool on_lid =
        m.feature_point.group == 3 && m.feature_point.index >= 1 && m.feature_point.index <= 4;
    if (on_lid && m.kind == tracking::MarkerKind::Dot) o.lid_markers_on_margin = false;
  }
  o.marker_priors = place_nominal_markers(nominal, prior.points);
  // A tag lies on the skin: the layout's nominal depth for it is a guess made on another head
  // (on the default head the middle tag's nominal place floats 12 mm in front of the forehead,
  // which read as a 1-2 degree pose error and 8 % FAP error under 25 degree turns). The
  // nearest outward-facing skin vertex of the prior is the better guess.
  if (!prior.skin.empty())
    for (const auto& m : nominal) {
      if (m.feature_point && prior.points.count(*m.feature_point)) continue;
      Eigen::Vector3d& x = o.marker_priors.at(m.id);
      const Eigen::Vector3d* best = nullptr;
      double best_d = std::numeric_limits<double>::max();
      for (const Eigen::Vector3d& v : prior.skin)
        if (const double d = (v - x).squaredNorm(); d < best_d) best_d = d, best = &v;
      x = *best;
    }
  return o;
}

}  // namespace rostro::calib
