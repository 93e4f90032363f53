#include "apps/face_trackers.hpp"

#include <fmt/format.h>

#include <filesystem>

#include "calib/actor_prior.hpp"
#include "tracking/ibug_mapping.hpp"
#include "tracking/layout.hpp"

namespace rostro::app {

void FaceTrackerArgs::add_options(CLI::App* cmd, bool required) {
  layout_required = required;
  cmd->add_option("--layout", layout,
                  required ? "Marker layout JSON (not with --markerless)"
                           : "Marker layout JSON (default: data/layouts/default.json)");
  cmd->add_flag("--markerless", markerless,
                "Track a bare face: 68 landmarks from dlib's model instead of worn markers");
  cmd->add_option("--landmark-model", landmarks.model,
                  "dlib 68-point shape predictor (default: " +
                      tracking::default_landmark_model().string() + ", Debian's libdlib-data)");
  cmd->add_option("--face", landmarks.face_rank,
                  "With --markerless and several faces in view: 1 the largest, 2 the next, ...")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--tracker-option", tracker_options,
                  "Set a marker tracker option, NAME=VALUE (repeatable; the names are "
                  "TrackerOptions' fields, e.g. identification.shape_factor=100 turns the shape "
                  "test off)");
}

namespace {

void check_choice(const FaceTrackerArgs& a) {
  if (a.markerless && !a.layout.empty())
    throw CLI::ValidationError("--layout", "a marker layout and --markerless exclude each other");
  if (!a.markerless && a.layout.empty() && a.layout_required)
    throw CLI::ValidationError("--layout", "give a marker layout (--layout FILE) or --markerless");
  if (a.markerless && !a.tracker_options.empty())
    throw CLI::ValidationError("--tracker-option",
                               "sets a marker tracker option, not one of --markerless");
}

}  // namespace

tracking::TrackerOptions with_tracker_options(const std::vector<std::string>& assignments,
                                              tracking::TrackerOptions base) {
  for (const std::string& a : assignments) tracking::set_tracker_option(base, a);
  base.validate();
  return base;
}

tracking::TrackerOptions FaceTrackerArgs::marker_options(tracking::TrackerOptions base) const {
  return with_tracker_options(tracker_options, std::move(base));
}

std::unique_ptr<tracking::FaceTracker> FaceTrackerArgs::make(
    const tracking::TrackerOptions& base) const {
  check_choice(*this);
  // The default head's feature points place the landmarks for calibration, as they place
  // markers on feature points.
  if (markerless)
    return std::make_unique<tracking::LandmarkTracker>(tracking::default_ibug_mapping(),
                                                       calib::load_actor_prior().points, landmarks);
  return std::make_unique<tracking::MarkerTracker>(make_layout(), marker_options(base));
}

std::string identification_report(const tracking::FaceTracker& tracker, double fps) {
  const auto* markers = dynamic_cast<const tracking::MarkerTracker*>(&tracker);
  if (markers == nullptr || markers->identification().dots == 0) return {};
  const tracking::IdentificationConfidence& c = markers->identification();
  if (markers->started_at() >= 0)
    return fmt::format("identified on frame {} ({:.2f} s): {}", markers->started_at(),
                       static_cast<double>(markers->started_at()) / (fps > 0 ? fps : 25),
                       tracking::describe(c));
  return fmt::format("never identified with confidence (last tried: {}: {})", tracking::describe(c),
                     c.doubt);
}

tracking::MarkerLayout FaceTrackerArgs::make_layout() const {
  check_choice(*this);
  if (markerless)
    return tracking::landmark_layout(tracking::default_ibug_mapping(),
                                     calib::load_actor_prior().points);
  return tracking::load_layout(layout.empty() ? tracking::default_layout_path()
                                              : std::filesystem::path(layout));
}

}  // namespace rostro::app
