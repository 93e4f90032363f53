#pragma once
// The tracker options every face-tracking command shares (track, calibrate actor, capture,
// live, eval loop): a marker layout, or --markerless with its landmark model, and the tracker
// they make. Wiring only: the trackers are tracking/'s.

#include <CLI/CLI.hpp>
#include <memory>
#include <string>
#include <vector>

#include "tracking/face_tracker.hpp"
#include "tracking/landmark_tracker.hpp"
#include "tracking/marker_tracker.hpp"

namespace rostro::app {

// `base` with each NAME=VALUE assignment (--tracker-option) set on it. Throws InputError
// naming an unknown field or a bad value.
tracking::TrackerOptions with_tracker_options(const std::vector<std::string>& assignments,
                                              tracking::TrackerOptions base = {});

struct FaceTrackerArgs {
  std::string layout;  // marker layout JSON; empty: the default one (or none with markerless)
  bool layout_required = true;  // without --markerless, --layout must be given
  bool markerless = false;
  tracking::LandmarkTrackerOptions landmarks;
  std::vector<std::string> tracker_options;  // --tracker-option NAME=VALUE, markers only

  // --layout (required unless --markerless when `required`), --markerless, --landmark-model,
  // --face, --tracker-option.
  void add_options(CLI::App* cmd, bool required);
  // `base` with every --tracker-option set on it. Throws InputError naming an unknown field or
  // a bad value.
  tracking::TrackerOptions marker_options(tracking::TrackerOptions base = {}) const;
  // A MarkerTracker on the layout (with marker_options(base)), or a LandmarkTracker. Throws
  // CLI::ValidationError when a required --layout is missing or given with --markerless, or
  // --tracker-option is given with --markerless, InputError for a bad layout, landmark model
  // or tracker option.
  std::unique_ptr<tracking::FaceTracker> make(const tracking::TrackerOptions& base = {}) const;
  // The layout make()'s tracker would have, without loading a landmark model: for tracks
  // that come from a CSV.
  tracking::MarkerLayout make_layout() const;
};

// How the markers were identified, in a line: "identified on frame 12 (0.48 s): 30/31 dots,
// ..., tags 3/3 read, 3 agree", or "never identified with confidence (frame 149: 12/31 dots,
// ...: 0 of 3 tags read)"; empty for a bare face's tracker or one given starting positions.
std::string identification_report(const tracking::FaceTracker& tracker, double fps);

}  // namespace rostro::app
