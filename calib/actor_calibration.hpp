#pragma once
// An actor profile from tracked frames of the neutral face:
//   1. each marker's neutral image position is its median over the frames where it is valid;
//   2. the head pose is the fit of the face prior's feature points, scaled per axis to the
//      actor, to those positions, the actor assumed to face the camera;
//   3. each marker's 3D neutral position is its image ray cut at the depth the prior gives
//      that feature point (x/y are the actor's own, depth is the prior's);
//   4. the FAPU come from that 3D shape (and, for seed2d, from the image), estimating the
//      FAPU points that carry no marker (calib/fapu_estimation.hpp).

#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "calib/actor_profile.hpp"
#include "calib/camera_intrinsics.hpp"
#include "tracking/tracked_frame.hpp"

namespace rostro::calib {

// A dot painted beside its feature point (tracking::MarkerSpec::beside_mm) as the face prior
// has it: its place on the prior's skin and the prior head's deformation there.
struct PriorPlace {
  Eigen::Vector3d position;  // prior frame, mm
  FapMotion motion;          // as ActorProfile::marker_motion
};

struct ActorCalibrationOptions {
  std::string name = "actor";
  // The 3D prior: feature points of a face in mm (x to the face's left, y up, z out of the
  // face). Null: the built-in generic face (calib/generic_face.hpp).
  const FeaturePointPositions* prior = nullptr;
  std::string prior_name = "rostro's built-in generic face";
  // A marker valid in fewer than this fraction of the neutral frames is left out.
  double min_valid_fraction = 0.5;
  // Prior positions (prior frame) of markers on no feature point or on one the prior lacks,
  // e.g. headband tags; place_nominal_markers() makes them from a layout.
  std::map<std::string, Eigen::Vector3d> marker_priors;
  // How firmly the neutral head is taken to face the camera: a tilt of 1 degree costs as much
  // as a 1 px error on a third of the markers, times this. One frontal view cannot tell a
  // pitched head from a shorter face, so this assumption decides.
  double facing_prior = 1.0;
  // Markers that only move with the skull: they constrain the pose and carry no FAPs.
  std::set<std::string> rigid_markers;
  // The prior head's deformation at its feature points (see ActorProfile::marker_motion); null:
  // FAPs move their own point along fap_axis(). Copied to every non-rigid marker on such a point.
  const std::map<FeaturePointId, FapMotion>* motion = nullptr;
  // The lid markers (3.1-3.4) lie on the lid margins, as landmarks do, and measure IRISD0;
  // painted dots sit beside them (see estimate_fapu).
  bool lid_markers_on_margin = true;
  // Dots painted beside their feature point, by marker id: the neutral pose is fitted to their
  // own places, the profile takes the prior's motion there, and the FAPU the feature point (the
  // dot's place less its offset, scaled to the actor).
  std::map<std::string, PriorPlace> beside;
};

// A marker's nominal position as a layout gives it (any frame aligned with the prior's axes:
// x to the face's left, y up, z out of the face; any origin and scale).
struct NominalMarker {
  std::string id;
  std::optional<FeaturePointId> feature_point;
  Eigen::Vector3d position;
};

// Every nominal marker moved into the prior's frame by the scale and offset that best match
// the markers on feature points the prior knows. Throws InputError when fewer than two match.
std::map<std::string, Eigen::Vector3d> place_nominal_markers(
    const std::vector<NominalMarker>& markers, const FeaturePointPositions& prior);

// Throws InputError when there are no frames or fewer than four usable markers.
ActorProfile calibrate_actor(const std::vector<tracking::TrackedFrame>& neutral_frames,
                             const CameraIntrinsics& camera,
                             const ActorCalibrationOptions& options = {});

// The calibration redone at another focal length (fx = fy = focal_px), from what `profile`
// keeps: its neutral image positions, and its own 3D shape as the prior (so the result is
// the shape the first calibration would have made with that focal length). Gains, motion and
// notes are kept; the camera's source is kept too (a refined default stays a default).
ActorProfile recalibrate_focal(const ActorProfile& profile, double focal_px);

}  // namespace rostro::calib
