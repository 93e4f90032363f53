// `rostro calibrate camera` and `rostro calibrate actor`: wiring only. Capture gives frames,
// tracking follows the markers, calib computes intrinsics and the actor profile.

#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "apps/checks.hpp"
#include "apps/commands.hpp"
#include "apps/face_trackers.hpp"
#include "apps/progress.hpp"
#include "calib/actor_prior.hpp"
#include "calib/camera_intrinsics.hpp"
#include "calib/chessboard_calibration.hpp"
#include "calib/neutral_motion.hpp"
#include "capture/open_source.hpp"
#include "facecore/error.hpp"
#include "tracking/layout.hpp"
#include "tracking/name_corrections.hpp"

namespace rostro::app {

namespace {

cv::Size parse_size(const std::string& text, const char* what) {
  int w = 0, h = 0;
  if (std::sscanf(text.c_str(), "%dx%d", &w, &h) != 2 || w <= 0 || h <= 0)
    throw InputError(std::string(what) + " '" + text + "': expected WIDTHxHEIGHT, e.g. 9x6");
  return {w, h};
}

void run_calibrate_camera(const std::string& source_spec, const std::string& board,
                          double square_mm, int every, int max_views, const std::string& output) {
  auto source = capture::open_frame_source(source_spec);
  calib::ChessboardSpec spec{parse_size(board, "--board"), square_mm};
  std::vector<cv::Mat> images;
  Progress progress("reading", source->frame_count() > 0 ? source->frame_count() : 0);
  long n = 0;
  while (auto frame = source->next()) {
    if (n++ % std::max(1, every) == 0) images.push_back(frame->image.clone());
    progress.update(n);
    if (static_cast<int>(images.size()) >= max_views) break;
  }
  progress.finish();
  const auto result = calib::calibrate_camera(images, spec);
  calib::write_intrinsics(output, result.intrinsics);
  const auto& k = result.intrinsics;
  std::printf(
      "%s: fx %.1f fy %.1f cx %.1f cy %.1f, reprojection error %.3f px (%d views, %d "
      "without the board)\n",
      output.c_str(), k.fx, k.fy, k.cx, k.cy, k.reprojection_error, result.views_used,
      result.views_rejected);
}

struct ActorArgs {
  FaceTrackerArgs face;
  std::string source, camera, output, name = "actor";
  double seconds = 1.0;
};

void run_calibrate_actor(const ActorArgs& a) {
  check_not_an_input({{a.output, "-o"}}, {a.source, a.camera});
  check_seconds(a.seconds, "--seconds");
  const std::unique_ptr<tracking::FaceTracker> tracker = a.face.make();
  const tracking::MarkerLayout& layout = tracker->layout();
  auto source = capture::open_frame_source(a.source);
  const double fps = source->nominal_fps() > 0 ? source->nominal_fps() : 25.0;
  const long wanted = std::max(1L, static_cast<long>(a.seconds * fps + 0.5));
  std::vector<tracking::TrackedFrame> frames;
  cv::Size size;
  // Frames read before the face is found do not count, up to a minute of them.
  long read = 0;
  const long max_read = static_cast<long>(60 * fps);
  while (static_cast<long>(frames.size()) < wanted) {
    auto frame = source->next();
    if (!frame) break;
    size = frame->image.size();
    const tracking::TrackedFrame tracked =
        tracker->track(frame->image, static_cast<long>(frames.size()), frame->timestamp_s);
    // The neutral window starts where the face is first found.
    if (tracker->started()) tracking::append_corrected(frames, tracked);
    if (++read > max_read && frames.empty()) break;
  }
  if (frames.empty())
    throw InputError(a.source +
                     (read == 0           ? ": no frames to calibrate from"
                      : a.face.markerless ? ": no face found in the first "
                                          : ": no markers identified in the first ") +
                     (read == 0 ? "" : std::to_string(read) + " frames"));
  std::string camera_note;
  const calib::CameraIntrinsics camera =
      a.camera.empty() ? calib::default_intrinsics(size)
                       : calib::intrinsics_for_frames(calib::read_intrinsics(a.camera), size,
                                                      a.camera, &camera_note);
  if (!camera_note.empty()) std::fprintf(stderr, "rostro calibrate: %s\n", camera_note.c_str());
  const auto motion = calib::measure_neutral_motion(frames);
  if (const std::string moving = calib::neutral_motion_warning(motion); !moving.empty())
    std::fprintf(stderr, "rostro calibrate: warning: %s\n", moving.c_str());
  const calib::ActorPrior prior = calib::load_actor_prior();
  const auto profile = calib::calibrate_actor(
      frames, camera, calib::actor_calibration_options(layout, prior, a.name));
  calib::write_actor_profile(a.output, profile);
  std::printf(
      "%s: %zu markers from %zu neutral frames; ES0 %.1f ENS0 %.1f MNS0 %.1f MW0 %.1f "
      "IRISD0 %.1f mm\n",
      a.output.c_str(), profile.markers.size(), frames.size(), profile.fapu.es0, profile.fapu.ens0,
      profile.fapu.mns0, profile.fapu.mw0, profile.fapu.irisd0);
  if (motion)
    std::printf("neutral frames: the face moves at most %.1f %% of its size ('%s', %.1f px)\n",
                100 * motion->share(), motion->marker.c_str(), motion->displacement_px);
  for (const auto& [point, how] : profile.fapu_notes)
    std::printf("  %s: %s\n", point.c_str(), how.c_str());
}

}  // namespace

void add_calibrate_commands(CLI::App& app) {
  auto* cal = app.add_subcommand("calibrate", "Calibrate the camera or an actor's neutral face");
  cal->require_subcommand(1);
  cal->footer(
      "Example:\n  rostro calibrate actor neutral.mp4 --layout data/layouts/default.json -o "
      "actor.json");

  auto* cam =
      cal->add_subcommand("camera", "Camera intrinsics from chessboard views (OpenCV FileStorage)");
  static std::string cam_source, board = "9x6", cam_out = "camera.yml";
  static double square = 25;
  static int every = 1, max_views = 40;
  cam->add_option("SOURCE", cam_source, "Image folder, video file or /dev/videoN")->required();
  cam->add_option("--board", board, "Inner corners per row x column")->capture_default_str();
  cam->add_option("--square", square, "Square edge in mm")->capture_default_str();
  cam->add_option("--every", every, "Use every Nth frame of a video")->capture_default_str();
  cam->add_option("--max-views", max_views, "Stop after this many frames")->capture_default_str();
  cam->add_option("-o,--output", cam_out, "Output .yml, .yaml, .xml or .json")
      ->capture_default_str();
  cam->footer(
      "Example:\n  rostro calibrate camera chessboard_photos/ --board 9x6 --square 25 -o "
      "camera.yml");
  cam->callback([] { run_calibrate_camera(cam_source, board, square, every, max_views, cam_out); });

  auto* actor = cal->add_subcommand(
      "actor", "Actor profile (FAPU, neutral markers in 2D and 3D) from a neutral take");
  static ActorArgs args;
  actor
      ->add_option("SOURCE", args.source,
                   "Video, image folder or /dev/videoN showing the neutral face")
      ->required();
  args.face.add_options(actor, true);
  actor->add_option("--camera", args.camera,
                    "Camera intrinsics (default: f = image width, centred)");
  actor->add_option("--seconds", args.seconds, "Neutral seconds to use from the start")
      ->capture_default_str();
  actor->add_option("--name", args.name, "Actor name stored in the profile")->capture_default_str();
  actor->add_option("-o,--output", args.output, "Actor profile JSON")->required();
  actor->footer(
      "Examples:\n  rostro calibrate actor neutral.mp4 --layout data/layouts/default.json --camera "
      "camera.yml -o actor.json\n  rostro calibrate actor neutral.mp4 --markerless -o actor.json");
  actor->callback([] { run_calibrate_actor(args); });
}

}  // namespace rostro::app
