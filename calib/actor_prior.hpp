#pragma once
// The 3D prior actor calibration starts from, and the layout's markers placed on it: shared
// by `rostro calibrate actor`, `rostro capture` and `rostro live`.

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "calib/actor_calibration.hpp"
#include "facecore/face_model.hpp"
#include "facecore/fapu.hpp"
#include "tracking/layout.hpp"

namespace rostro::calib {

struct ActorPrior {
  FeaturePointPositions points;
  std::string name;  // says which prior was used, for the profile's notes
  // The head's deformation at each feature point: FAP id -> displacement of one FAP unit in
  // multiples of that FAP's FAPU (so it scales to any actor through the actor's FAPU). Empty
  // for the generic face, which has no deformation model.
  std::map<FeaturePointId, std::map<int, Eigen::Vector3d>> motion;
  // The prior head's skin facing the camera (vertices whose normal points out of the face):
  // where markers on no feature point (headband tags) are pressed onto it. Empty for the
  // generic face, whose markers then keep the layout's nominal places.
  std::vector<Eigen::Vector3d> skin;
  // The prior head and its deformation at every vertex (as `motion`), for the dots painted
  // beside their point (place_beside); null for the generic face.
  std::shared_ptr<const FaceModel> head;
  std::shared_ptr<const std::vector<FapMotion>> vertex_motion;
};

// Vertices of `model` whose area-weighted normal points out of the face (+z).
std::vector<Eigen::Vector3d> front_skin(const FaceModel& model);

// The linear deformation of `model` at every vertex, as ActorPrior::motion (couplings under 1 %
// of a FAPU per FAPU left out).
std::vector<FapMotion> vertex_motion(const FaceModel& model);
// The same at its feature points.
std::map<FeaturePointId, std::map<int, Eigen::Vector3d>> feature_point_motion(
    const FaceModel& model);

// A dot painted `beside` (x, y mm) feature point `fp` on the prior head: the skin there seen
// from the front, and the head's motion there. nullopt without a head, or with no skin there.
std::optional<PriorPlace> place_beside(const ActorPrior& prior, FeaturePointId fp,
                                       const Eigen::Vector2d& beside);

// The prior of `head`: its feature points, skin and deformation.
ActorPrior actor_prior(std::shared_ptr<const FaceModel> head);
// The default head's prior, or rostro's built-in generic face when no head loads.
ActorPrior load_actor_prior();

// Calibration options for `layout` on `prior`: nominal marker positions and rigid markers.
// `prior` must outlive the options (they point at its points).
ActorCalibrationOptions actor_calibration_options(const tracking::MarkerLayout& layout,
                                                  const ActorPrior& prior, const std::string& name);

}  // namespace rostro::calib
