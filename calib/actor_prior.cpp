#include "calib/actor_prior.hpp"

#include <optional>
#include <vector>

#include "calib/generic_face.hpp"
#include "facecore/error.hpp"
#include "facecore/face_model.hpp"

namespace rostro::calib {

ActorPrior load_actor_prior() {
  try {
    const FaceModel head = load_default_face_model();
    return {head.feature_point_positions(), "the default head (" + head.name + ")"};
  } catch (const InputError&) {
    return {generic_face_points(), "rostro's built-in generic face"};
  }
}

ActorCalibrationOptions actor_calibration_options(const tracking::MarkerLayout& layout,
                                                  const ActorPrior& prior,
                                                  const std::string& name) {
  ActorCalibrationOptions o;
  o.name = name;
  o.prior = &prior.points;
  o.prior_name = prior.name;
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
