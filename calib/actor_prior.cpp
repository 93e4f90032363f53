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
#include "facecore/surface_point.hpp"

namespace rostro::calib {

namespace {

// Couplings under 1 % of a FAPU per FAPU are noise of the deformation's fall-off.
FapMotion without_negligible(FapMotion motion) {
  for (auto it = motion.begin(); it != motion.end();)
    it = it->second.norm() < 0.01 ? motion.erase(it) : std::next(it);
  return motion;
}

// Per vertex, every FAP's step in multiples of its FAPU, the negligible ones kept.
std::vector<FapMotion> raw_vertex_motion(const FaceModel& model) {
  const Eigen::SparseMatrix<double> map = Deformer(model).linear_map();  // 3V x 68
  std::vector<FapMotion> out(model.positions.size());
  for (int col = 0; col < map.outerSize(); ++col) {
    const int id = col + 1;
    // Head rotation (48-50) is the pose; eyeball turns (23-26) are rotations, not linear.
    if (id < 3 || (id >= 23 && id <= 26) || (id >= 48 && id <= 50)) continue;
    const double unit = model.fapu.unit_size(fap_info(id).unit);
    if (!(unit > 0)) continue;
    for (Eigen::SparseMatrix<double>::InnerIterator it(map, col); it; ++it) {
      const auto row = static_cast<std::size_t>(it.row());
      auto& step = out[row / 3].try_emplace(id, Eigen::Vector3d::Zero()).first->second;
      step[static_cast<Eigen::Index>(row % 3)] += it.value() / unit;
    }
  }
  return out;
}

// The motion of each feature point's vertex that has any.
std::map<FeaturePointId, FapMotion> at_feature_points(const FaceModel& model,
                                                      const std::vector<FapMotion>& motion) {
  std::map<FeaturePointId, FapMotion> out;
  for (const auto& [fp, v] : model.feature_points)
    if (!motion[static_cast<std::size_t>(v)].empty()) out[fp] = motion[static_cast<std::size_t>(v)];
  return out;
}

}  // namespace

std::vector<FapMotion> vertex_motion(const FaceModel& model) {
  std::vector<FapMotion> out = raw_vertex_motion(model);
  for (FapMotion& m : out) m = without_negligible(std::move(m));
  return out;
}

std::map<FeaturePointId, std::map<int, Eigen::Vector3d>> feature_point_motion(
    const FaceModel& model) {
  return at_feature_points(model, vertex_motion(model));
}

std::optional<PriorPlace> place_beside(const ActorPrior& prior, FeaturePointId fp,
                                       const Eigen::Vector2d& beside) {
  if (!prior.head || !prior.vertex_motion || !prior.head->has_feature_point(fp))
    return std::nullopt;
  const Eigen::Vector3d point = prior.head->feature_point(fp);
  const auto skin = front_skin_point(*prior.head, point.x() + beside.x(), point.y() + beside.y());
  if (!skin) return std::nullopt;
  PriorPlace place;
  place.position = skin->on(prior.head->positions).cast<double>();
  for (std::size_t k = 0; k < 3; ++k) {
    const auto w = static_cast<double>(skin->weights[static_cast<Eigen::Index>(k)]);
    for (const auto& [id, step] :
         (*prior.vertex_motion)[static_cast<std::size_t>(skin->vertices[k])])
      place.motion.try_emplace(id, Eigen::Vector3d::Zero()).first->second += w * step;
  }
  place.motion = without_negligible(std::move(place.motion));
  return place;
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

ActorPrior actor_prior(std::shared_ptr<const FaceModel> head) {
  auto motion = std::make_shared<const std::vector<FapMotion>>(vertex_motion(*head));
  return {head->feature_point_positions(),
          "the head " + head->name,
          at_feature_points(*head, *motion),
          front_skin(*head),
          head,
          motion};
}

ActorPrior load_actor_prior() {
  try {
    ActorPrior prior = actor_prior(std::make_shared<const FaceModel>(load_default_face_model()));
    prior.name = "the default head (" + prior.head->name + ")";
    return prior;
  } catch (const InputError&) {
    return {generic_face_points(), "rostro's built-in generic face", {}, {}, nullptr, nullptr};
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
    if (is_eyelid_midpoint(m.feature_point) && m.kind == tracking::MarkerKind::Dot)
      o.lid_markers_on_margin = false;
    if (m.beside_mm && fp)
      if (auto place = place_beside(prior, *fp, {m.beside_mm->x, m.beside_mm->y}))
        o.beside[m.id] = *place;
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
