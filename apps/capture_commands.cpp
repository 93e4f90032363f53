// `rostro capture`: frames (or a tracks CSV) in, a .fap out, streamed frame by frame so that
// Ctrl-C or a camera unplugged mid-take leaves a valid file of every frame so far. Wiring
// only: capture -> tracking -> mapping::PipelinedTakeMapper (calib when no profile, then the
// fit, on a worker thread while the next frame is tracked) -> facecore's .fap sink.

#include <algorithm>
#include <cstdio>
#include <deque>
#include <memory>
#include <optional>
#include <string>

#include "apps/checks.hpp"
#include "apps/commands.hpp"
#include "apps/face_trackers.hpp"
#include "apps/interrupt.hpp"
#include "apps/progress.hpp"
#include "calib/camera_intrinsics.hpp"
#include "calib/neutral_motion.hpp"
#include "capture/open_source.hpp"
#include "facecore/error.hpp"
#include "facecore/expression_library.hpp"
#include "facecore/face_model.hpp"
#include "facecore/fap_io.hpp"
#include "mapping/fap_mapper.hpp"
#include "mapping/pipelined_take_mapper.hpp"
#include "render/face_renderer.hpp"
#include "render/preview.hpp"
#include "render/video_writer.hpp"
#include "tracking/layout.hpp"
#include "tracking/name_corrections.hpp"
#include "tracking/start_backfill.hpp"
#include "tracking/tracks_csv.hpp"

namespace rostro::app {

namespace {

struct CaptureArgs {
  FaceTrackerArgs face;
  std::string source, actor, camera, output, tracks, preview, method = "ceres", size = "1280x720";
  bool no_hierarchy = false;
  double calibration_seconds = 1.0;
};

// Tracked frames from a frame source through the tracker, or straight from a tracks CSV.
class TrackedInput {
 public:
  explicit TrackedInput(const CaptureArgs& a) {
    if (a.source.size() > 4 && a.source.substr(a.source.size() - 4) == ".csv") {
      layout_ = a.face.make_layout();
      reader_ = std::make_unique<tracking::TracksReader>(a.source);
      int w = 0, h = 0;
      if (std::sscanf(a.size.c_str(), "%dx%d", &w, &h) != 2 || w <= 0 || h <= 0)
        throw InputError("--size '" + a.size + "': expected WIDTHxHEIGHT");
      size_ = {w, h};
    } else {
      tracker_ = a.face.make();
      held_ = tracking::CorrectionWindow(tracker_->correction_horizon());
      backfill_ =
          std::make_unique<tracking::StartBackfill>(*tracker_, tracker_->correction_horizon());
      source_ = capture::open_frame_source(a.source);
      size_ = source_->frame_size();
      fps_ = source_->nominal_fps();
      total_ = source_->frame_count();
    }
  }
  // `view`, when given, receives the camera image with the tracker's markers drawn on it. The
  // tracker's frames come a few behind its images, held until no later frame can correct
  // their names (tracking/name_corrections.hpp); the take's end hands them all out.
  bool next(tracking::TrackedFrame& out, cv::Mat* view = nullptr) {
    if (reader_) return !stopped_ && reader_->next(out);
    while (ready_.empty() && !stopped_) {
      auto frame = source_->next();
      if (!frame) {
        stop();
        break;
      }
      tracking::TrackedFrame tracked = tracker_->track(frame->image, index_++, frame->timestamp_s);
      backfill_->take(tracked, held_.held(), frame->image);
      if (view != nullptr) {
        views_.push_back(frame->image.clone());
        tracker_->draw(views_.back(), tracked.frame);
      }
      for (auto& f : held_.push(std::move(tracked))) ready_.push_back(std::move(f));
    }
    if (ready_.empty()) return false;
    out = std::move(ready_.front());
    ready_.pop_front();
    if (view != nullptr && !views_.empty()) {
      *view = views_.front();
      views_.pop_front();
    }
    return true;
  }
  // No more images are read: next() hands out the frames still held (a take stopped early).
  void stop() {
    stopped_ = true;
    for (auto& f : held_.flush()) ready_.push_back(std::move(f));
  }
  const tracking::MarkerLayout& layout() const { return tracker_ ? tracker_->layout() : layout_; }
  // False while a tracker has not found the face yet (markers identified, a face detected).
  bool face_found() const { return !tracker_ || tracker_->started(); }
  // identification_report() of the tracker ("" for tracks from a CSV).
  std::string identification() const {
    return tracker_ ? identification_report(*tracker_, fps()) : std::string();
  }
  bool has_images() const { return source_ != nullptr; }
  cv::Size size() const { return size_; }
  double fps() const { return fps_ > 0 ? fps_ : 25.0; }
  long total() const { return total_ > 0 ? static_cast<long>(total_) : 0; }

 private:
  std::unique_ptr<tracking::TracksReader> reader_;
  std::unique_ptr<capture::FrameSource> source_;
  tracking::MarkerLayout layout_;  // of a tracks CSV
  std::unique_ptr<tracking::FaceTracker> tracker_;
  tracking::CorrectionWindow held_{0};
  // The frames before the start still held, filled by following the markers back from it.
  std::unique_ptr<tracking::StartBackfill> backfill_;
  std::deque<tracking::TrackedFrame> ready_;  // corrected, not yet handed out
  std::deque<cv::Mat> views_;                 // the images of the frames held and ready
  bool stopped_ = false;
  cv::Size size_;
  double fps_ = 0;
  std::int64_t total_ = -1;
  long index_ = 0;
};

// The preview video: the camera image with markers beside the default head animated by the
// FAPs of the same frame.
class CapturePreview {
 public:
  CapturePreview(const std::string& path, double fps, int height)
      : model_(load_default_face_model()),
        library_(ExpressionLibrary::load_default()),
        face_(model_, &library_, head_options(height)),
        video_(path, video_options(fps)) {}
  void write(const cv::Mat& camera, const FapFrame& faps) {
    video_.write(render::compose_preview(camera, face_.render(faps, render::CameraPose::front())));
  }
  void finish() { video_.finish(); }

 private:
  static render::VideoOptions video_options(double fps) {
    render::VideoOptions o;
    o.fps = fps;
    return o;
  }
  static render::RenderOptions head_options(int height) {
    render::RenderOptions o;
    o.width = o.height = (std::clamp(height, 240, 720) + 1) & ~1;
    return o;
  }
  FaceModel model_;
  ExpressionLibrary library_;
  render::FaceRenderer face_;
  render::VideoWriter video_;
};

// Where a take that failed part-way is kept: take.fap -> take.partial.fap.
std::filesystem::path partial_name(const std::string& output) {
  const std::filesystem::path p(output);
  return p.parent_path() / (p.stem().string() + ".partial" + p.extension().string());
}

void run_capture(const CaptureArgs& a) {
  check_seconds(a.calibration_seconds, "--calibration-seconds");
  check_not_an_input({{a.output, "-o"}, {a.tracks, "--tracks"}, {a.preview, "--preview"}},
                     {a.source, a.actor, a.camera});
  TrackedInput input(a);
  const tracking::MarkerLayout& layout = input.layout();
  mapping::MapperOptions options;
  options.method = mapping::parse_method(a.method);
  if (!a.no_hierarchy) options.hierarchy = mapping::default_hierarchy();

  if (!a.preview.empty() && !input.has_images())
    throw InputError(
        "--preview needs frames: give a video, image folder or camera, not a tracks CSV");
  const bool want_views = !a.preview.empty();
  std::optional<calib::ActorProfile> profile;
  if (!a.actor.empty()) profile = calib::read_actor_profile(a.actor);
  // --camera wins; else the profile's own intrinsics; else the documented default.
  std::string camera_note;
  const calib::CameraIntrinsics camera =
      !a.camera.empty() ? calib::intrinsics_for_frames(calib::read_intrinsics(a.camera),
                                                       input.size(), a.camera, &camera_note)
      : profile ? calib::intrinsics_for_frames(profile->camera, input.size(), a.actor + "'s camera",
                                               &camera_note)
                : calib::default_intrinsics(input.size());
  if (!camera_note.empty()) std::fprintf(stderr, "rostro capture: %s\n", camera_note.c_str());
  const long calibration_frames =
      std::max(1L, static_cast<long>(a.calibration_seconds * input.fps() + 0.5));
  // The fit runs on a second core, a frame or a few behind the tracking: push() hands back
  // the frames mapped so far, finish() the rest (and after Ctrl-C or a lost camera too).
  mapping::PipelinedTakeMapper take(layout, options, camera, std::move(profile),
                                    calibration_frames);

  FapHeader header;
  header.name = "rostro-capture";
  header.fps = input.fps();
  auto sink = open_fap_sink(a.output, header);
  std::unique_ptr<tracking::TracksWriter> tracks;
  if (!a.tracks.empty()) tracks = std::make_unique<tracking::TracksWriter>(a.tracks);
  std::unique_ptr<CapturePreview> preview;
  if (want_views)
    preview = std::make_unique<CapturePreview>(a.preview, input.fps(), input.size().height);

  std::deque<cv::Mat> views;  // preview images of the frames the mapper holds back
  long done = 0;
  bool announced = false;
  Progress progress("capture", input.total());
  // Writes the FAP frames the mapper hands back, each beside its own camera image.
  const auto write = [&](const std::vector<FapFrame>& ready) {
    if (take.self_calibrated() && !announced) {
      announced = true;
      std::fprintf(stderr,
                   "rostro capture: no --actor given: calibrated the actor from the first %ld "
                   "frames (%.1f s), assumed neutral%s\n",
                   take.calibration_frames_used(), a.calibration_seconds,
                   a.camera.empty() ? ", with default camera intrinsics" : "");
      if (const std::string moving = calib::neutral_motion_warning(take.calibration_motion());
          !moving.empty())
        std::fprintf(stderr, "rostro capture: warning: %s\n", moving.c_str());
    }
    for (const FapFrame& faps : ready) {
      sink->write(faps);
      if (preview) {
        preview->write(views.front(), faps);
        views.pop_front();
      }
      progress.update(++done);
    }
  };

  InterruptScope interrupt;
  // A failure of the input (a camera gone, a bad row) keeps every frame so far; a failure of
  // an output (a full disk) keeps the frames that reached the disk whole. Either way the
  // take goes under its own name, and an earlier take of the requested name stays.
  std::optional<std::string> failure;
  bool output_failed = false;
  long pushed = 0;
  const auto guarded_write = [&](const std::vector<FapFrame>& ready) {
    try {
      write(ready);
    } catch (const InputError& e) {
      failure = e.what();
      output_failed = true;
    }
  };
  tracking::TrackedFrame f;
  cv::Mat view;
  // Takes the input's next frame into the take; false at its end or on a failure.
  const auto take_next = [&] {
    try {
      if (!input.next(f, want_views ? &view : nullptr)) return false;
      if (tracks) tracks->write(f);
    } catch (const InputError& e) {
      failure = e.what();
      return false;
    }
    ++pushed;
    if (want_views) views.push_back(view);
    guarded_write(take.push(f));
    return true;
  };
  while (!interrupt.requested() && !failure && take_next()) {
  }
  // Stopped early (a signal, a camera gone): the frames the input still holds are the take's.
  input.stop();
  while (!output_failed && take_next()) {
  }
  if (pushed == 0 && !failure) {
    if (interrupt.requested()) interrupt.throw_if_requested();
    throw InputError(a.source + (input.has_images() ? ": no frame could be read"
                                                    : ": the tracks file has no frames"));
  }
  if (!input.face_found() && !interrupt.requested() && !failure)
    throw InputError(a.source +
                     (a.face.markerless ? std::string(": no face found in any frame")
                                        : ": the markers were " + input.identification()) +
                     "; nothing written");
  // A stopped or broken take with nothing held back (queued, in the fit, or waiting for the
  // calibration) has nothing left to calibrate or map.
  if (!output_failed && (take.held_back() > 0 || !(failure || interrupt.requested()))) {
    try {
      guarded_write(take.finish());
    } catch (const InputError& e) {
      if (!failure) failure = e.what();
    }
  }
  progress.finish();
  if (failure) {
    const std::filesystem::path partial = partial_name(a.output);
    std::string kept = "nothing was captured; " + a.output + " is untouched";
    if (sink->frames_written() > 0) {
      sink->finish_as(partial);
      kept = "the " + std::to_string(sink->frames_written()) + " frames before it are saved in " +
             partial.string() + "; " + a.output + " is untouched";
      if (tracks && !output_failed) {
        try {
          tracks->finish_as(partial_name(a.tracks));
          kept += "; the tracks in " + partial_name(a.tracks).string();
        } catch (const InputError&) {
          // The tracks are a by-product: the FAPs are what the take keeps.
        }
      }
    }
    throw InputError(*failure + " (" + kept + ")");
  }
  sink->finish();
  warn_if_xface_cannot_read(*sink, a.output);
  if (tracks) tracks->finish();
  if (preview) preview->finish();
  std::printf(
      "%s: %ld frames%s\n", a.output.c_str(), sink->frames_written(),
      interrupt.requested() ? (" (stopped by " + interrupt.signal_name() + ")").c_str() : "");
  if (const std::string identified = input.identification(); !identified.empty())
    std::printf("%s\n", identified.c_str());
}

}  // namespace

void add_capture_commands(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "capture", "Track an actor's markers or bare face and write MPEG-4 FAPs (.fap)");
  static CaptureArgs a;
  cmd->add_option("SOURCE", a.source, "Video file, image folder, /dev/videoN, or a tracks .csv")
      ->required();
  a.face.add_options(cmd, true);
  cmd->add_option(
      "--actor", a.actor,
      "Actor profile from 'rostro calibrate actor' (default: calibrate from the first second)");
  cmd->add_option("--camera", a.camera, "Camera intrinsics (OpenCV FileStorage)");
  cmd->add_option("-o,--output", a.output, "Output .fap (or .csv/.json)")->required();
  cmd->add_option("--tracks", a.tracks, "Also write the tracks CSV here");
  cmd->add_option("--preview", a.preview,
                  "Also write an .mp4: the camera image with markers beside the animated head");
  cmd->add_option("--method", a.method,
                  "ceres (head pose + FAP fit) or seed2d (the seed's 2D baseline)")
      ->capture_default_str();
  cmd->add_flag("--no-hierarchy", a.no_hierarchy, "Write only the measured FAPs, derive none");
  cmd->add_option("--calibration-seconds", a.calibration_seconds,
                  "Neutral seconds used when no --actor is given")
      ->capture_default_str();
  cmd->add_option("--size", a.size, "Image size of a tracks .csv source (for default intrinsics)")
      ->capture_default_str();
  cmd->footer(
      "Ctrl-C, SIGTERM or SIGHUP stop the take and keep every frame so far. A take that fails\n"
      "part-way (a camera unplugged, a bad row, a full disk) is kept as NAME.partial.fap and an\n"
      "earlier NAME.fap stays. After a crash or SIGKILL, 'rostro fap recover NAME.fap.tmp-PID'\n"
      "gives back every frame up to the last second. With --markerless a bare face is tracked\n"
      "by its 68 landmarks (dlib); frames where it is not found carry no FAPs.\n\n"
      "Examples:\n  rostro capture take.mp4 "
      "--layout data/layouts/default.json --actor actor.json -o take.fap --tracks take.csv\n"
      "  rostro capture face.mp4 --markerless -o face.fap --preview face-preview.mp4");
  cmd->callback([] { run_capture(a); });
}

}  // namespace rostro::app
