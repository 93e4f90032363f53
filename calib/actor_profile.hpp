#pragma once
// What `rostro calibrate actor` learns about one actor and `rostro capture` needs: the
// actor's FAPU, the neutral position of every marker (2D, and 3D in the head frame where
// known), the camera intrinsics the 3D part assumes, and optional per-FAP gains or ranges.
// Stored as JSON (docs/mapping.md describes every field).

#include <Eigen/Core>
#include <filesystem>
#include <map>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "calib/camera_intrinsics.hpp"
#include "facecore/fapu.hpp"
#include "tracking/tracked_frame.hpp"

namespace rostro::calib {

struct NeutralMarker {
  std::string marker;  // the layout's marker id
  FeaturePointId feature_point;
  cv::Point2d image;  // median neutral position, pixels
  // Neutral position in the head frame (mm; x to the face's left, y up, z out of the face),
  // when the 3D shape could be built.
  std::optional<Eigen::Vector3d> position;
  int frames_seen = 0;  // neutral frames in which the marker was valid
  bool rigid = false;   // moves only with the skull (headband tag): pose only
};

// How one unit of each FAP moves a marker, in multiples of that FAP's FAPU (head frame): the
// prior head's own deformation at the marker's point (or, for a dot painted beside it, at the
// dot's place), cross-effects included (open_jaw carries the lower lip along). FAP id -> step.
using FapMotion = std::map<int, Eigen::Vector3d>;

// A correction applied to a mapped FAP: value * gain, then clamped to [min, max] where set.
struct FapGain {
  double gain = 1.0;
  std::optional<double> min;
  std::optional<double> max;
};

struct ActorProfile {
  std::string name = "actor";
  Fapu fapu;        // from the 3D neutral shape, mm: what the Ceres fit divides by
  Fapu fapu_image;  // from the neutral image, px (y up): what seed2d divides by
  // Feature point -> how it was obtained when no marker sits on it ("3.5": "midpoint of ...").
  std::map<std::string, std::string> fapu_notes;
  CameraIntrinsics camera;
  // Neutral head pose, head frame -> camera frame (Rodrigues, mm); the fit's first guess.
  std::optional<tracking::HeadPose> neutral_pose;
  std::string shape_source;  // where the 3D neutral shape came from
  int neutral_frames = 0;
  std::vector<NeutralMarker> markers;
  std::map<int, FapGain> fap_gains;  // FAP id -> gain/range
  // Marker id -> its FapMotion (JSON: the marker's "motion"). A marker without one: each FAP
  // of its point moves it along fap_axis(), nothing else does.
  std::map<std::string, FapMotion> marker_motion;

  const NeutralMarker* find_marker(const std::string& id) const;
  // Applies fap_gains to a FAP value of FAP `id`.
  double apply_gain(int id, double value) const;
};

// Throws InputError "path: what" for a missing file, bad JSON or a bad field.
ActorProfile read_actor_profile(const std::filesystem::path& path);
// Written atomically (an earlier file survives any failure).
void write_actor_profile(const std::filesystem::path& path, const ActorProfile& profile);

// The JSON text itself (for tests and for embedding); `context` prefixes parse errors.
std::string actor_profile_to_json(const ActorProfile& profile);
ActorProfile actor_profile_from_json(const std::string& text, const std::string& context);

}  // namespace rostro::calib
