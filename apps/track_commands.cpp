// `rostro track`: a video (or camera, or image folder) in, the tracks CSV out, and an
// optional overlay video showing each marker's id and state. Wiring only: capture gives
// frames, tracking follows the markers.

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <opencv2/videoio.hpp>
#include <optional>
#include <string>

#include "apps/checks.hpp"
#include "apps/commands.hpp"
#include "apps/face_trackers.hpp"
#include "apps/interrupt.hpp"
#include "apps/progress.hpp"
#include "capture/open_source.hpp"
#include "facecore/error.hpp"
#include "tracking/identify.hpp"
#include "tracking/layout.hpp"
#include "tracking/marker_tracker.hpp"
#include "tracking/name_corrections.hpp"
#include "tracking/overlay.hpp"
#include "tracking/start_backfill.hpp"
#include "tracking/tracks_csv.hpp"

namespace rostro::app {
namespace {

struct TrackArgs {
  std::string source;
  FaceTrackerArgs face;
  std::string output;
  std::string overlay;
  std::string start;  // starting positions (tracks CSV) instead of identification
  double fps = 0;     // image folders
  long max_frames = 0;
  tracking::TrackerOptions options;
  std::string polarity;  // overrides the layout's
};

// The marker tracker with track's own options (polarity, starting positions), or the
// landmark tracker.
std::unique_ptr<tracking::FaceTracker> make_tracker(const TrackArgs& args) {
  if (args.face.markerless) {
    if (!args.start.empty() || !args.polarity.empty())
      throw CLI::ValidationError("--markerless", "--start and --polarity are for markers");
    return args.face.make();
  }
  tracking::MarkerLayout layout =
      tracking::load_layout(args.face.layout.empty() ? tracking::default_layout_path()
                                                     : std::filesystem::path(args.face.layout));
  if (args.polarity == "dark") layout.polarity = tracking::DotPolarity::Dark;
  if (args.polarity == "bright") layout.polarity = tracking::DotPolarity::Bright;
  auto tracker =
      std::make_unique<tracking::MarkerTracker>(layout, args.face.marker_options(args.options));
  if (!args.start.empty())
    tracker->set_start_positions(tracking::read_start_positions(args.start, tracker->layout()));
  return tracker;
}

void run_track(const TrackArgs& args) {
  if (args.fps != 0) check_fps(args.fps, "--fps");
  check_not_an_input({{args.output, "-o"}, {args.overlay, "--overlay"}}, {args.source, args.start});
  const std::unique_ptr<tracking::FaceTracker> tracker = make_tracker(args);
  const tracking::MarkerLayout& layout = tracker->layout();

  capture::SourceOptions source_options;
  source_options.fps = args.fps;
  auto source = capture::open_frame_source(args.source, source_options);

  tracking::TracksWriter writer(args.output);
  // The overlay is written beside its destination under a temporary name (keeping the
  // extension, which picks the container) and renamed at the end, like every output.
  cv::VideoWriter overlay;
  std::filesystem::path overlay_temp;
  struct RemoveTemp {
    std::filesystem::path* path;
    ~RemoveTemp() {
      std::error_code ignored;
      if (!path->empty()) std::filesystem::remove(*path, ignored);
    }
  } remove_temp{&overlay_temp};
  if (!args.overlay.empty()) {
    const std::filesystem::path dest(args.overlay);
    overlay_temp = dest;
    overlay_temp.replace_filename(dest.stem().string() + ".tmp-" + std::to_string(::getpid()) +
                                  dest.extension().string());
    const double fps = source->nominal_fps() > 0 ? source->nominal_fps() : 25;
    if (!overlay.open(overlay_temp.string(), cv::VideoWriter::fourcc('m', 'p', '4', 'v'), fps,
                      source->frame_size()))
      throw InputError(args.overlay + ": cannot write an overlay video (mp4v codec)");
  }

  long total = source->frame_count() > 0 ? static_cast<long>(source->frame_count()) : 0;
  if (args.max_frames > 0 && (total == 0 || args.max_frames < total)) total = args.max_frames;
  Progress progress("track", total);
  long frame = 0, never_started = 0;
  long valid_sum = 0, marker_sum = 0;
  // A signal stops the run; the tracks of every frame so far are kept.
  InterruptScope interrupt;
  // The last frames wait for the names the tracker may still correct in them.
  tracking::CorrectionWindow held(tracker->correction_horizon());
  // The frames before the start still held are filled by following the markers back from it.
  tracking::StartBackfill backfill(*tracker, tracker->correction_horizon());
  const auto write = [&](const std::vector<tracking::TrackedFrame>& ready) {
    for (const tracking::TrackedFrame& t : ready) {
      writer.write(t);
      for (const auto& m : t.markers) valid_sum += m.valid, ++marker_sum;
    }
  };
  while ((args.max_frames <= 0 || frame < args.max_frames) && !interrupt.requested()) {
    auto f = source->next();
    if (!f) break;
    tracking::TrackedFrame tracked = tracker->track(f->image, frame, f->timestamp_s);
    if (!tracker->started()) ++never_started;
    if (backfill.take(tracked, held.held(), f->image) > 0)
      std::fprintf(stderr, "rostro track: frame %ld: frames %ld-%ld followed back from it\n", frame,
                   backfill.filled_from(), frame - 1);
    // The identification is reported at the end; a check during the take that renamed a dot
    // (or gave two their dots back), as it happens.
    if (!tracked.identification.empty() && tracked.identification.starts_with("identities"))
      std::fprintf(stderr, "rostro track: frame %ld: %s\n", frame, tracked.identification.c_str());
    if (!tracked.corrections.empty())
      std::fprintf(stderr, "rostro track: frame %ld: %s\n", frame,
                   tracking::describe_corrections(tracked).c_str());
    write(held.push(std::move(tracked)));
    if (overlay.isOpened()) {
      cv::Mat image = f->image.clone();
      tracker->draw(image, frame);
      overlay.write(image);
    }
    ++frame;
    progress.update(frame);
  }
  write(held.flush());
  progress.finish();
  if (frame == 0) {
    interrupt.throw_if_requested();
    throw InputError(args.source + ": no frames to track");
  }
  // A bare face that never shows gives no tracks at all: nothing is written.
  const double fps = source->nominal_fps() > 0 ? source->nominal_fps() : 25;
  const std::string identified = identification_report(*tracker, fps);
  // Markers never identified with confidence give no tracks either: a take named wrongly
  // from its first frame is worse than none.
  if (!args.face.markerless && never_started == frame && !interrupt.requested())
    throw InputError(
        args.source + ": the markers were " +
        (identified.empty() ? std::string("not found at the starting positions") : identified) +
        "; nothing written (give their positions with --start)");
  if (args.face.markerless && never_started == frame && !interrupt.requested())
    throw InputError(args.source + ": no face found in any of its " + std::to_string(frame) +
                     " frames (faces narrower than " +
                     std::to_string(static_cast<int>(args.face.landmarks.min_face_px)) +
                     " px are not searched for)");
  writer.finish();
  if (overlay.isOpened()) {
    overlay.release();
    std::error_code ec;
    std::filesystem::rename(overlay_temp, args.overlay, ec);
    if (ec)
      throw InputError(args.overlay + ": cannot move the overlay into place: " + ec.message());
    overlay_temp.clear();
  }
  const auto stats = source->stats();
  std::printf(
      "%ld frames tracked%s, %ld markers, %.1f%% of marker positions valid, %ld dropped\n", frame,
      interrupt.requested() ? (" (stopped by " + interrupt.signal_name() + ")").c_str() : "",
      static_cast<long>(layout.markers.size()),
      marker_sum ? 100.0 * static_cast<double>(valid_sum) / static_cast<double>(marker_sum) : 0.0,
      static_cast<long>(stats.dropped));
  if (!identified.empty()) {
    std::printf("%s\n", identified.c_str());
    if (never_started > 0 && never_started < frame) {
      const std::string filled = backfill.filled_from() < backfill.started_at()
                                     ? ", but frames " + std::to_string(backfill.filled_from()) +
                                           "-" + std::to_string(backfill.started_at() - 1) +
                                           " with the markers followed back from it"
                                     : "";
      std::printf("the %ld frames before it are written with every marker invalid%s\n",
                  never_started, filled.c_str());
    }
  }
}

}  // namespace

void add_track_commands(CLI::App& app) {
  static TrackArgs args;
  CLI::App* cmd = app.add_subcommand(
      "track",
      "Track markers (dots, AprilTags) or a bare face's landmarks and write the tracks CSV");
  cmd->add_option("SOURCE", args.source, "Video file, image folder, /dev/videoN or libcamera:N")
      ->required();
  args.face.add_options(cmd, false);
  cmd->add_option("-o,--output", args.output,
                  "Tracks CSV to write (frame,time_s,marker,fp,x,y,valid,quality)")
      ->required();
  cmd->add_option("--overlay", args.overlay,
                  "Also write a video with each marker's id and state (.mp4)");
  cmd->add_option(
      "--start", args.start,
      "Starting positions (a tracks CSV; its first frame) instead of automatic identification");
  cmd->add_option("--fps", args.fps, "Frame rate of an image folder")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--max-frames", args.max_frames, "Stop after this many frames (0: all)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--dot-min", args.options.dots.min_diameter_px, "Smallest dot diameter, pixels")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--dot-max", args.options.dots.max_diameter_px, "Largest dot diameter, pixels")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--dot-contrast", args.options.dots.min_contrast,
                  "Least grey-level contrast of a dot against the skin around it")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--polarity", args.polarity,
                  "Dots darker or brighter than the skin (default: the layout's)")
      ->check(CLI::IsMember({"dark", "bright"}));
  cmd->add_option("--tag-decimation", args.options.tags.decimation,
                  "AprilTag quad decimation on the first frame (1: small tags, slower)")
      ->check(CLI::Range(1.0, 8.0));
  cmd->add_option("--tag-threads", args.options.tags.threads, "AprilTag detector threads")
      ->check(CLI::Range(1, 64));
  cmd->add_option("--max-fb-error", args.options.max_fb_error,
                  "Largest forward-backward LK error (pixels) before a dot is flagged invalid")
      ->check(CLI::PositiveNumber);
  cmd->footer(
      "Markers: the take should start with the face frontal and every marker visible: they are\n"
      "identified with no clicks (the tags first, then each dot near where dlib's landmarks of\n"
      "this face and its named neighbours put it) on the first frame that identifies them with\n"
      "confidence (tags read and agreeing, most dots found, each name clear of the next\n"
      "detection, no motion blur, the face found); the frames before it are written invalid,\n"
      "and a take with no such frame is an error (give --start). The identification is printed\n"
      "and kept in the CSV as a '# identification:' comment. Markers that are hidden or fail\n"
      "the checks are written with valid=0 and come back with their own identity when they\n"
      "reappear.\n"
      "--markerless: the largest face (or --face N) is found by dlib's face detector and its 68\n"
      "landmarks are written under their MPEG-4 feature points; frames without a face are\n"
      "written invalid, and a clip with no face at all is an error.\n\n"
      "Examples:\n"
      "  rostro track take.mp4 --layout data/layouts/default.json -o take.tracks.csv --overlay "
      "take.overlay.mp4\n"
      "  rostro track face.mp4 --markerless -o face.tracks.csv --overlay face.overlay.mp4");
  cmd->callback([] { run_track(args); });
}

}  // namespace rostro::app
