// `rostro synth`: render a clip of the default head wearing the marker layout, with exact
// ground-truth tracks, the driving .fap and the camera intrinsics.

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "apps/checks.hpp"
#include "apps/commands.hpp"
#include "apps/interrupt.hpp"
#include "apps/progress.hpp"
#include "calib/camera_intrinsics.hpp"
#include "eval/head_sweeps.hpp"
#include "eval/synth.hpp"
#include "facecore/error.hpp"
#include "facecore/fap_io.hpp"
#include "render/video_writer.hpp"
#include "tracking/ibug_mapping.hpp"
#include "tracking/tracks_csv.hpp"

namespace rostro::app {
namespace {

struct SynthArgs {
  std::string output, fap, layout, face_model, size = "640x480";
  double fps = 25, seconds = 0, neutral_lead = 0;
  eval::SynthOptions o;
  eval::HeadSweeps head;  // turns written into the drive's FAPs 48-50
  bool no_markers = false;
};

void synth(SynthArgs a) {
  if (a.output.empty()) throw InputError("-o/--output: a path prefix is required");
  int w = 0, h = 0;
  char x = 0;
  if (std::sscanf(a.size.c_str(), "%d%c%d", &w, &x, &h) != 3 || x != 'x' || w < 16 || h < 16 ||
      w > 8192 || h > 8192)
    throw InputError("--size " + a.size + ": expected WIDTHxHEIGHT within 16..8192, e.g. 640x480");
  a.o.width = w;
  a.o.height = h;
  check_fps(a.fps, "--fps");
  if (a.seconds != 0) check_seconds(a.seconds, "--seconds");
  if (a.neutral_lead != 0) check_seconds(a.neutral_lead, "--neutral-lead", 3600);

  FapStream drive = a.fap.empty() ? eval::range_of_motion(a.fps) : read_fap_stream(a.fap);
  if (a.seconds > 0) {
    const auto keep = static_cast<std::size_t>(std::lround(a.seconds * drive.header.fps));
    if (keep < drive.frames.size()) drive.frames.resize(keep);
  }
  if (a.neutral_lead > 0) eval::prepend_neutral(drive, a.neutral_lead);
  a.head.start_s = std::max(0.0, a.neutral_lead);  // the lead stays still for calibration
  eval::add_head_sweeps(drive, a.head);
  drive.header.frame_count = static_cast<long>(drive.frames.size());

  const FaceModel model = load_face_model_or_default(a.face_model);
  const ExpressionLibrary library = ExpressionLibrary::load_default();
  if (a.no_markers && !a.layout.empty())
    throw CLI::ValidationError("--no-markers", "renders no layout; leave out --layout");
  // Bare: the landmark layout places the truth on the feature points and paints nothing.
  const tracking::MarkerLayout layout =
      a.no_markers ? tracking::landmark_layout(tracking::default_ibug_mapping(),
                                               model.feature_point_positions())
                   : tracking::load_layout(a.layout.empty() ? tracking::default_layout_path()
                                                            : std::filesystem::path(a.layout));
  const auto painted = eval::place_markers(model, layout);
  a.o.dot_diameter_mm = layout.dot_diameter_mm;
  a.o.dark_dots = layout.polarity == tracking::DotPolarity::Dark;
  if (painted.empty()) throw InputError("the layout has no marker that can be placed on the head");

  // The prefix's folder is made, as `-o clips/turn` asks.
  if (const auto folder = std::filesystem::path(a.output).parent_path(); !folder.empty())
    std::filesystem::create_directories(folder);
  const std::string video = a.output + ".mp4";
  render::VideoOptions vo;
  vo.fps = drive.header.fps;
  render::VideoWriter sink(video, vo);
  Progress progress("rendering", static_cast<long>(drive.frames.size()));
  // A signal abandons the clip: its video, truth and drive are written together or not at all.
  InterruptScope interrupt;
  const eval::SynthResult r =
      eval::synthesize(model, &library, painted, drive, a.o, sink, [&](long done) {
        interrupt.throw_if_requested();
        progress.update(done);
      });
  interrupt.throw_if_requested();
  progress.finish();
  tracking::write_tracks(a.output + ".truth.csv", r.truth);
  write_fap_stream(a.output + ".fap", drive);
  calib::write_intrinsics(a.output + ".intrinsics.yml", r.intrinsics);
  const auto tags = std::count_if(painted.begin(), painted.end(),
                                  [](const eval::PaintedMarker& m) { return m.spec->is_tag(); });
  if (a.no_markers)
    std::printf("%s: %zu frames, bare; truth at %zu feature points\n", video.c_str(),
                drive.frames.size(), painted.size());
  else
    std::printf("%s: %zu frames, %zu dots and %ld AprilTags\n", video.c_str(), drive.frames.size(),
                painted.size() - static_cast<std::size_t>(tags), static_cast<long>(tags));
  std::printf("%s.truth.csv, %s.fap, %s.intrinsics.yml\n", a.output.c_str(), a.output.c_str(),
              a.output.c_str());
}

}  // namespace

void add_synth_commands(CLI::App& app) {
  static SynthArgs a;
  CLI::App* cmd = app.add_subcommand(
      "synth",
      "Render a clip of the default head, or another by --head (with markers or bare), with "
      "exact ground truth");
  cmd->add_option("-o,--output", a.output,
                  "path prefix: writes PREFIX.mp4, .truth.csv, .fap, .intrinsics.yml")
      ->required();
  cmd->add_option("--fap", a.fap, "FAP stream driving the face (default: a range-of-motion clip)");
  cmd->add_option("--layout", a.layout, "marker layout JSON (default data/layouts/default.json)");
  cmd->add_option("--head", a.face_model,
                  "face model JSON to render, e.g. from rostro head (default: the default head)");
  cmd->add_flag("--no-markers", a.no_markers,
                "render the head bare (for --markerless); the truth is its feature points "
                "that the iBUG landmarks name");
  cmd->add_option("--seconds", a.seconds, "cut the clip to this length");
  cmd->add_option("--neutral-lead", a.neutral_lead,
                  "seconds of neutral face before the motion, for calibration by rostro capture");
  cmd->add_option("--fps", a.fps, "frame rate of the range-of-motion clip")->capture_default_str();
  cmd->add_option("--size", a.size, "image size WIDTHxHEIGHT")->capture_default_str();
  cmd->add_option("--fov", a.o.fov_deg, "vertical field of view, degrees")->capture_default_str();
  cmd->add_option("--distance-scale", a.o.distance_scale,
                  "camera distance relative to the automatic framing")
      ->capture_default_str();
  cmd->add_option("--yaw", a.o.yaw_deg,
                  "camera orbit left-right, degrees (moves the view, not the FAPs)");
  cmd->add_option("--pitch", a.o.pitch_deg, "camera orbit up-down, degrees");
  cmd->add_option("--elevation", a.o.elevation_deg,
                  "camera held this many degrees above the face (below if negative)");
  cmd->add_option("--roll", a.o.roll_deg, "camera tilt, degrees");
  cmd->add_option("--motion-period", a.o.motion_period_s, "seconds per camera sweep")
      ->capture_default_str();
  cmd->add_option("--head-yaw", a.head.yaw_deg,
                  "head turn amplitude, degrees, written into the drive's FAP 49 (after the "
                  "neutral lead), so the truth .fap has it");
  cmd->add_option("--head-pitch", a.head.pitch_deg,
                  "head nod amplitude, degrees, into FAP 48 (at 0.73 x the yaw's frequency)");
  cmd->add_option("--head-roll", a.head.roll_deg, "head tilt amplitude, degrees, into FAP 50");
  cmd->add_option("--head-period", a.head.period_s, "seconds per head sweep")
      ->capture_default_str();
  cmd->add_option("--distance-amp", a.o.distance_amp, "relative distance change, e.g. 0.1");
  cmd->add_option("--brightness", a.o.brightness, "overall gain (0.4: low light)")
      ->capture_default_str();
  cmd->add_option("--light", a.o.light_amp, "slow brightness dips of up to this share (0..1)");
  cmd->add_option("--noise", a.o.noise_sigma, "Gaussian sensor noise, grey levels");
  cmd->add_option("--motion-blur", a.o.motion_blur, "shutter open share of a frame (0..1)");
  cmd->add_flag("--occluder", a.o.occluder, "a hand-sized blob passes across the lower face");
  cmd->add_option("--seed", a.o.seed, "seed of every random choice")->capture_default_str();
  cmd->footer(
      "Example:\n  rostro synth -o clips/turn --yaw 25 --pitch 15 --noise 3 --seed 7\n"
      "  rostro synth -o clips/nod --neutral-lead 1 --head-yaw 25 --head-pitch 15\n"
      "  rostro track clips/turn.mp4 -o turn.tracks.csv   # then\n"
      "  rostro eval tracks --truth clips/turn.truth.csv --tracks turn.tracks.csv\n"
      "  rostro synth -o clips/bare --no-markers --neutral-lead 1 --seconds 4\n"
      "  rostro capture clips/bare.mp4 --markerless -o bare.fap");
  cmd->callback([] { synth(a); });
}

}  // namespace rostro::app
