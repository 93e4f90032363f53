#pragma once
// Synthetic clips with exact ground truth (`rostro synth`): the default head animated by a
// FAP stream, the layout's dots painted on the skin so they move and deform with it, seen by
// a moving camera, with optional lighting changes, sensor noise, motion blur and a passing
// occluder, all seeded so a clip is reproducible.
//
// Each dot is a disc of the layout's diameter lying on the skin at its place (below):
// the disc (in the tangent plane of the deformed surface there) is projected through the same
// camera matrices the renderer uses and drawn over the rendered face, so it moves, turns and
// foreshortens with the skin. The mesh is too coarse to carry a 4 mm dot in its vertex
// colours (a painted vertex smears over its triangles), hence the decal.
// Ground truth is the exact projection of the dot's centre. A dot is visible (and drawn) when
// its place faces the camera, lies inside the image and is not under the occluder. Being
// hidden behind other geometry (the nose at a large turn) is judged by the facing test only.
// AprilTags of the layout are not drawn yet (the renderer has vertex colours, no textures);
// their markers are left out of the clip and of the truth.

#include <Eigen/Core>
#include <functional>
#include <vector>

#include "calib/camera_intrinsics.hpp"
#include "facecore/expression_library.hpp"
#include "facecore/face_model.hpp"
#include "facecore/fap_frame.hpp"
#include "facecore/surface_point.hpp"
#include "render/frame_sink.hpp"
#include "tracking/layout.hpp"
#include "tracking/tracked_frame.hpp"

namespace rostro::eval {

constexpr double kMaxElevationDeg = 60;

struct SynthOptions {
  int width = 640;
  int height = 480;
  double fov_deg = 25.0;        // vertical field of view
  double distance_scale = 1.0;  // camera distance relative to the automatic framing
  // Head motion, as the camera orbiting the head: sine sweeps of these amplitudes.
  double yaw_deg = 0, pitch_deg = 0, roll_deg = 0;
  double motion_period_s = 4.0;  // one full left-right (up-down) sweep
  // The camera held this far above the face's level, degrees (below when negative), looking
  // down (up) at it; the pitch sweep swings about it. At most kMaxElevationDeg either way.
  double elevation_deg = 0;
  double distance_amp = 0;       // relative distance change (0.1: +-10 %)
  double brightness = 1.0;       // overall gain; below 1 for low light
  double light_amp = 0;          // slow brightness dips of up to this share (0..1)
  double noise_sigma = 0;        // Gaussian sensor noise, grey levels
  double motion_blur = 0;        // share of the frame interval the shutter is open (0..1)
  bool occluder = false;         // a hand-sized blob passes across the lower face
  double dot_diameter_mm = 4.0;  // the layout's
  bool dark_dots = true;         // the layout's polarity
  unsigned seed = 1;
};

struct PaintedMarker {
  const tracking::MarkerSpec* spec = nullptr;
  SurfacePoint place;  // dots: the dot's centre, its feature point's vertex or beside it
  // Tags: the neutral plane (centre, unit axes: right and up as the tag is read, normal out of
  // the head) and the rigid vertices that carry it.
  Eigen::Vector3f centre = Eigen::Vector3f::Zero();
  Eigen::Vector3f right = Eigen::Vector3f::UnitX(), up = Eigen::Vector3f::UnitY();
  Eigen::Vector3f normal = Eigen::Vector3f::UnitZ();
  std::vector<int> anchors;
};

// The layout's dots that sit on a feature point of `model`, centred on that point's vertex or,
// for a dot the layout paints beside its point (MarkerSpec::beside_mm), on the skin there
// (seen from the front), then its AprilTags placed on the head (see above). Dots on feature points
// the model lacks are left out. A landmark layout's markers (tracking::MarkerKind::Landmark) are
// placed like dots but not painted: the head is rendered bare, and the truth is the feature points'
// projection.
std::vector<PaintedMarker> place_markers(const FaceModel& model,
                                         const tracking::MarkerLayout& layout);

// A built-in range-of-motion sequence: jaw, lip corners, lips, brows and eyelids in turn,
// each eased in and out over one second.
FapStream range_of_motion(double fps);

// Puts `seconds` of the neutral face (no FAP set) before the stream's frames and renumbers
// them, so that a capture calibrating from the first second sees a neutral face there.
void prepend_neutral(FapStream& stream, double seconds);

struct SynthResult {
  std::vector<tracking::TrackedFrame> truth;
  calib::CameraIntrinsics intrinsics;
};

// Renders every frame of `drive` into `sink` (finishing it) and returns the truth. `model`
// Throws render::RenderUnavailable without OpenGL.
SynthResult synthesize(const FaceModel& model, const ExpressionLibrary* library,
                       const std::vector<PaintedMarker>& markers, const FapStream& drive,
                       const SynthOptions& options, render::FrameSink& sink,
                       const std::function<void(long)>& progress = {});

}  // namespace rostro::eval
