#pragma once
// The per-frame fit: head pose (angle-axis + translation) and the FAPs of the marked feature
// points, minimising the markers' reprojection error. Each marker's 3D position is its
// neutral position moved by the FAPs acting on it (value x actor FAPU along fap_axis()).
// Robust loss, lower bounds for unidirectional FAPs (0; not the cheeks; open_jaw a little
// below), a weak pull toward the previous frame (weaker still for the jaw and outer lips, a
// hard one for FAPs a hidden marker leaves ambiguous), a pull of the head pose toward its
// smoothed prediction, warm-started from the previous frame (the pose at constant velocity). Ceres,
// with one parameter block (pose + FAPs) and analytic derivatives.

#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "calib/actor_profile.hpp"
#include "facecore/fap_frame.hpp"
#include "mapping/marker_model.hpp"
#include "tracking/tracked_frame.hpp"

namespace rostro::mapping {

enum class RobustLoss { None, Huber, Cauchy };

struct SolverOptions {
  // Declared so that GCC 12 does not warn (-Wmaybe-uninitialized, a false positive) on every
  // defaulted SolverOptions{} once the struct holds several containers.
  SolverOptions() = default;
  MarkerModelOptions model;
  RobustLoss loss = RobustLoss::Huber;
  double loss_scale_px = 2.0;  // residuals beyond this many pixels count less
  // Pull toward the previous frame (toward neutral on the first): a FAP change that moves
  // its marker by p pixels costs as much as a reprojection error of prior_weight x p.
  double prior_weight = 0.05;
  // Weaker pulls for some FAPs (id -> weight, replacing prior_weight): the jaw and the outer
  // lips. A frontal face barely shows a tenth of a degree of head pitch (hundredths of a
  // pixel), so the pull's lag on a fast mouth (the Xface lips swing 300 MNS a frame) goes into
  // the pose. Not everywhere: the eyelids' and the nose's dots are noisier and their FAPs do
  // not drag the pose; the firm pull smooths them.
  std::map<int, double> prior_weight_of = {
      {3, 0.005},  {15, 0.005}, {18, 0.005}, {51, 0.005}, {52, 0.005}, {53, 0.005}, {54, 0.005},
      {55, 0.005}, {56, 0.005}, {57, 0.005}, {58, 0.005}, {59, 0.005}, {60, 0.005}};
  // Pull of the head pose toward its prediction (the previous pose moved on by a smoothed
  // velocity): a pose change that moves the markers by p pixels (a rotation: at their RMS
  // distance from their centroid) costs as much as a reprojection error of
  // pose_prior_weight x p. A frontal face tells a small pitch (or yaw) from a vertical (or
  // sideways) move only by its depth, so the dots' frame-to-frame noise (hundredths of a
  // pixel) goes into the pitch of a still head. Well-seen motions are held by ~30 markers
  // against one prior and barely feel it; a turn lags a little. Measured on and off:
  // docs/rules.md. 0 turns it off.
  double pose_prior_weight = 0.5;
  // Beyond a miss of this many pixels the pose prior's pull stops growing (Huber): jitter is
  // a few hundredths of a pixel, while a quick head turn the prediction did not foresee (3
  // degrees a frame from rest) moves the markers by pixels, and a firm pull there went into
  // the FAPs instead (their own pulls are 10-100 times weaker).
  double pose_prior_scale_px = 0.2;
  // How fast the prediction's velocity follows the fitted poses (alpha-beta filter's beta): a
  // share of each frame's miss. The raw last-two-frames velocity (a gain of 1) is worse: its
  // noise is twice the pose's.
  double pose_velocity_gain = 0.2;
  int max_iterations = 25;
  // Ceres' stopping rules: relative cost change, relative step size.
  double function_tolerance = 1e-6;
  double parameter_tolerance = 1e-6;
  int min_markers = 4;    // fewer valid markers: the frame is not fitted
  bool head_faps = true;  // report the head rotation from neutral as FAPs 48-50
  // Unidirectional FAPs the fit still lets go below 0. The cheeks: the Xface streams draw
  // them down to -8 ENS (anger, fear, disgust) and the head renders that; clamped at 0, the
  // cheek dots' miss pulls the head pitch.
  std::set<int> signed_faps = {41, 42};
  // Unidirectional FAPs the fit lets go a little below 0 (id -> lowest value): open_jaw, which
  // the Xface streams close up to 7 MNS past neutral (the head renders it). Held at 0 the jaw
  // dots' miss goes into the head pitch; let go entirely, noise under head turns opens a
  // jaw-lip ambiguity. Reported
  // values still stop at 0, as the FAP table's direction says.
  std::map<int, double> lower_bounds = {{3, -10.0}};
  // FAPs held at the previous frame's value while every marker on a feature point is hidden.
  // Without the chin dot (2.1, hidden when the head is pitched down and turned) the chin boss
  // (2.10) and the lower lip move with open_jaw and with their own FAPs alike, so the fit
  // cannot tell a jaw opening from a chin or lip raise; holding depress_chin lets the chin
  // boss read the jaw.
  struct HoldWhileHidden {
    std::string feature_point;
    std::vector<int> faps;
  };
  std::vector<HoldWhileHidden> hold_while_hidden = {{"2.1", {18}}};
  // A FAP is reported only in frames where a marker that reads it is valid: one it moves at
  // least this share as far as the marker it moves most (its own point's). Through a marker
  // it barely moves (the outer brow's FAP through the mid-brow dot, 3 %) the fit cannot tell
  // it from its weak prior: with its own dot lost it stays where it was while the brow moves,
  // and is better left to the hierarchy's mirror of its measured twin, or unwritten.
  double min_reading_share = 0.1;
  // With default intrinsics (no --camera), the focal length is a guess that bends every FAP
  // once the head turns (a focal length 40 % short bends them by most of their range at 25
  // degrees of yaw). Refine it from the frames themselves: a recursive least-squares
  // estimate of log f from each fitted frame, its information marginalised over that frame's
  // pose and FAPs (a frontal face says almost nothing about f, a turned one does).
  bool refine_default_focal = true;
  double focal_prior_sigma = 0.2;  // of log f: how firmly the guess is held

  // Throws InputError naming the first option out of range (a negative weight,
  // max_iterations <= 0, ...). FapSolver's constructor calls it.
  void validate() const;
};

// Sets one scalar field of `options` from "NAME=VALUE" (NAME a field's name as above, e.g.
// "pose_prior_weight=0" or "model.fit_depth_faps=true"): for `rostro eval loop
// --solver-option`. Throws InputError for an unknown name or a bad value.
void set_solver_option(SolverOptions& options, const std::string& assignment);

struct FitResult {
  FapFrame faps;            // fitted FAPs (profile gains applied); 48-50 if head_faps
  tracking::HeadPose pose;  // head frame -> camera frame (OpenCV convention)
  double rms_px = 0;        // RMS reprojection error over the markers used
  int markers_used = 0;
  int iterations = 0;
  double focal_px = 0;  // the focal length (fx) this frame was fitted with
  bool ok = false;      // false: too few markers, nothing measured this frame
};

class FapSolver {
 public:
  explicit FapSolver(const calib::ActorProfile& profile, const SolverOptions& options = {});
  ~FapSolver();
  FapSolver(const FapSolver&) = delete;
  FapSolver& operator=(const FapSolver&) = delete;

  FitResult fit(const tracking::TrackedFrame& frame);
  // Forgets the previous frame: the next fit starts from the neutral pose and face.
  void reset();
  const MarkerModel& model() const;
  // The focal length (fx, px) the next frame will be fitted with: the profile's, or its
  // refined estimate (SolverOptions::refine_default_focal).
  double focal_length() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Head rotation relative to the neutral pose as FAP values (AU): pitch (48, down positive),
// yaw (49, toward the face's left), roll (50, toward the face's right); H = Ry Rx Rz.
std::array<double, 3> head_rotation_faps(const tracking::HeadPose& neutral,
                                         const tracking::HeadPose& pose);

}  // namespace rostro::mapping
