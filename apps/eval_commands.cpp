// `rostro eval ...`: score tracks and FAP streams against ground truth, with reports and plots.

#include <fmt/chrono.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <functional>
#include <optional>
#include <sstream>

#include "apps/checks.hpp"
#include "apps/commands.hpp"
#include "apps/face_trackers.hpp"
#include "apps/interrupt.hpp"
#include "apps/progress.hpp"
#include "eval/closed_loop.hpp"
#include "eval/eval_plots.hpp"
#include "eval/head_check.hpp"
#include "eval/photo_suite.hpp"
#include "eval/report.hpp"
#include "eval/speech_alignment.hpp"
#include "eval/suite.hpp"
#include "eval/track_metrics.hpp"
#include "eval/truth_tracks.hpp"
#include "facecore/error.hpp"
#include "facecore/expression_library.hpp"
#include "facecore/face_model.hpp"
#include "facecore/fap_io.hpp"
#include "mapping/fap_solver.hpp"
#include "render/video_writer.hpp"
#include "speech/forced_align.hpp"
#include "tracking/layout.hpp"
#include "tracking/marker_tracker.hpp"
#include "tracking/tracks_csv.hpp"

namespace rostro::app {
namespace {

// "2026-11-25 10:22 UTC": when a --markdown section was written.
std::string utc_now() {
  return fmt::format("{:%Y-%m-%d %H:%M} UTC", fmt::gmtime(std::time(nullptr)));
}

std::vector<std::string> split_commas(const std::string& text) {
  std::vector<std::string> parts;
  std::stringstream in(text);
  std::string part;
  while (std::getline(in, part, ',')) parts.push_back(part);
  return parts;
}

// Output paths are checked before any work, so a typo costs nothing: the file's kind, and the
// folder it goes in (written at the end, a missing one would fail a run of minutes at its end).
void check_output(const std::string& path, const char* ext, const char* option) {
  if (path.empty()) return;
  const std::filesystem::path file(path);
  if (file.extension() != ext)
    throw InputError(fmt::format("{} {}: expected a {} file", option, path, ext));
  const std::filesystem::path folder = file.parent_path();
  if (std::error_code ec; !folder.empty() && !std::filesystem::is_directory(folder, ec))
    throw InputError(
        fmt::format("{} {}: the folder {} does not exist", option, path, folder.string()));
}

struct TracksArgs {
  std::string truth, tracks, norm = "3.7,3.12", report, summary, ced, match = "auto", label,
                             pts_map;
  double threshold = eval::kDefaultAucThreshold, swap_threshold = 0.05, pts_fps = 30.0;
  long pts_first_frame = 0;
  bool lost_is_failure = false;
};

void eval_tracks(const TracksArgs& a) {
  check_output(a.report, ".json", "--report");
  check_output(a.summary, ".md", "--summary");
  check_output(a.ced, ".png", "--ced");
  check_fps(a.pts_fps, "--pts-fps");
  eval::TrackEvalOptions o;
  const auto norm = split_commas(a.norm);
  if (norm.size() != 2 || norm[0].empty() || norm[1].empty())
    throw InputError("--norm " + a.norm + ": expected two points 'A,B', e.g. 3.7,3.12");
  o.norm_a = norm[0];
  o.norm_b = norm[1];
  if (!(a.threshold > 0)) throw InputError("--threshold must be positive");
  if (a.swap_threshold < 0) throw InputError("--swap-threshold must not be negative");
  o.threshold = a.threshold;
  o.swap_threshold = a.swap_threshold;
  o.lost_is_failure = a.lost_is_failure;
  const bool pts = eval::is_pts_truth(a.truth);
  if (a.match == "marker")
    o.match = eval::MatchBy::Marker;
  else if (a.match == "fp" || (a.match == "auto" && pts))
    o.match = eval::MatchBy::FeaturePoint;
  else if (a.match == "auto")
    o.match = eval::MatchBy::Marker;
  else
    throw InputError("--match " + a.match + ": expected 'marker', 'fp' or 'auto'");

  eval::TruthOptions truth_options;
  truth_options.pts_mapping = a.pts_map;
  truth_options.pts_first_frame = a.pts_first_frame;
  truth_options.pts_fps = a.pts_fps;
  const auto truth = eval::read_truth_tracks(a.truth, truth_options);
  const auto estimate = tracking::read_tracks(a.tracks);
  const eval::TrackEvalResult r = eval::evaluate_tracks(truth, estimate, o);
  const eval::ReportSources sources{a.truth, a.tracks};

  if (!a.report.empty()) eval::write_text_file(a.report, eval::track_report_json(r, sources));
  if (!a.summary.empty())
    eval::write_text_file(a.summary, eval::track_summary_markdown(r, sources));
  if (!a.ced.empty()) {
    const std::string label =
        a.label.empty() ? std::filesystem::path(a.tracks).stem().string() : a.label;
    eval::write_png(a.ced, eval::draw_chart(eval::ced_chart({{label, r.frame_nme}}, o.threshold,
                                                            std::max(0.1, o.threshold * 1.25)),
                                            {900, 600}));
  }
  std::printf(
      "%ld frames scored (%ld missing)  NME mean %.4f median %.4f  AUC@%.2f %.3f  "
      "failure %.1f%%\n"
      "error px mean %.2f p95 %.2f  lost %ld observations in %ld frames  swaps %ld (%ld "
      "events)  astray %ld\n",
      r.scored_frames, r.missing_frames, r.nme.mean, r.nme.median, o.threshold, r.auc,
      100 * r.failure_rate, r.error_px.mean, r.error_px.p95, r.lost_observations, r.lost_frames,
      r.swap_observations, r.swap_events, r.astray_observations);
}

struct FapsArgs {
  std::string truth, est, report, summary, plot, faps;
};

void eval_faps(const FapsArgs& a) {
  check_output(a.report, ".json", "--report");
  check_output(a.summary, ".md", "--summary");
  check_output(a.plot, ".png", "--plot");
  std::vector<int> chosen;
  for (const std::string& part : split_commas(a.faps)) {
    int id = 0;
    try {
      std::size_t used = 0;
      id = std::stoi(part, &used);
      if (used != part.size()) id = 0;
    } catch (const std::exception&) {
      id = 0;
    }
    if (id < 3 || id > kFapCount)
      throw InputError("--faps " + a.faps + ": '" + part +
                       "' is not a low-level FAP number (3..68)");
    chosen.push_back(id);
  }
  const FapStream truth = read_fap_stream(a.truth);
  const FapStream est = read_fap_stream(a.est);
  const eval::FapEvalResult r = eval::evaluate_faps(truth, est);
  const eval::ReportSources sources{a.truth, a.est};
  if (!a.report.empty()) eval::write_text_file(a.report, eval::fap_report_json(r, sources));
  if (!a.summary.empty()) eval::write_text_file(a.summary, eval::fap_summary_markdown(r, sources));
  if (!a.plot.empty()) {
    if (chosen.empty()) chosen = eval::widest_range_faps(r, 3);
    for (int id : chosen) {
      const bool compared = std::any_of(r.faps.begin(), r.faps.end(),
                                        [id](const eval::FapError& e) { return e.fap == id; });
      if (compared) continue;
      std::string present;
      for (const eval::FapError& e : r.faps)
        present += (present.empty() ? "" : ",") + std::to_string(e.fap);
      throw InputError(fmt::format("--faps: FAP {} is not set in both streams (both set: {})", id,
                                   present.empty() ? "none" : present));
    }
    if (chosen.empty()) throw InputError("--plot: the two streams share no FAP to draw");
    eval::write_png(a.plot,
                    eval::draw_charts(eval::fap_curve_charts(truth, est, chosen), {1000, 280}));
  }
  std::printf(
      "%ld matched frames, %zu FAPs compared  mean RMS %.2f  mean RMS/range %s  "
      "mean correlation %s\n",
      r.matched_frames, r.faps.size(), r.mean_rms,
      r.mean_share_of_range ? fmt::format("{:.3f}", *r.mean_share_of_range).c_str() : "n/a",
      r.mean_correlation ? fmt::format("{:.3f}", *r.mean_correlation).c_str() : "n/a");
  std::printf("%-4s %-28s %7s %9s %9s %7s\n", "FAP", "name", "frames", "RMS", "RMS/range", "corr");
  for (const eval::FapError& f : r.faps)
    std::printf("%-4d %-28s %7ld %9.2f %9s %7s\n", f.fap, std::string(fap_info(f.fap).name).c_str(),
                f.frames, f.rms,
                f.rms_share_of_range ? fmt::format("{:.3f}", *f.rms_share_of_range).c_str() : "n/a",
                f.correlation ? fmt::format("{:.3f}", *f.correlation).c_str() : "n/a");
}

// The scenarios named by --only (all when it is empty); throws when it names none.
template <typename Scenario>
std::vector<Scenario> chosen_scenarios(const std::vector<Scenario>& all, const std::string& only) {
  std::vector<Scenario> chosen;
  const auto wanted = split_commas(only);
  for (const auto& s : all)
    if (wanted.empty() || std::find(wanted.begin(), wanted.end(), s.name) != wanted.end())
      chosen.push_back(s);
  if (chosen.empty()) throw InputError("--only " + only + ": no scenario of that name");
  return chosen;
}

// What the suite and the closed loop render: a head (the default one unless `head_path` names
// a face model JSON), its expressions, a layout.
struct Scene {
  Scene(const std::string& layout_path, const std::string& head_path)
      : model(load_face_model_or_default(head_path)),
        library(ExpressionLibrary::load_default()),
        layout(tracking::load_layout(layout_path.empty() ? tracking::default_layout_path()
                                                         : std::filesystem::path(layout_path))) {}
  FaceModel model;
  ExpressionLibrary library;
  tracking::MarkerLayout layout;
};

// `--out DIR` of eval suite and eval photos: a row's clip as rendered (NAME.mp4) and the tracks
// and truth behind it (NAME.tracks.csv, NAME.truth.csv), so that a row can be replayed with
// `rostro track NAME.mp4 --overlay ...` and read with `rostro eval tracks`. Nothing without it.
class RowOutput {
 public:
  RowOutput(const std::string& out, const std::string& name, double fps) : dir_(out), name_(name) {
    if (out.empty()) return;
    std::filesystem::create_directories(dir_);
    render::VideoOptions v;
    v.fps = fps;
    video_.emplace(dir_ / (name_ + ".mp4"), v);
  }
  // The frames' sink to hand the run: empty without --out.
  std::function<void(const cv::Mat&)> frames() {
    if (!video_) return {};
    return [this](const cv::Mat& bgr) { video_->write(bgr); };
  }
  void finish(const eval::SuiteRow& row) {
    if (!video_) return;
    video_->finish();
    tracking::write_tracks(dir_ / (name_ + ".tracks.csv"), row.tracks);
    tracking::write_tracks(dir_ / (name_ + ".truth.csv"), row.truth);
  }

 private:
  std::filesystem::path dir_;
  std::string name_;
  std::optional<render::VideoWriter> video_;
};

struct SuiteArgs {
  std::string suite, layout, head, markdown, only, out;
  std::vector<std::string> tracker_options;  // NAME=VALUE
};

// " with --tracker-option A=1 ...", for the report's first line; empty for the defaults.
std::string options_note(const std::vector<std::string>& tracker,
                         const std::vector<std::string>& solver) {
  std::string out;
  for (const std::string& a : tracker) out += " --tracker-option " + a;
  for (const std::string& a : solver) out += " --solver-option " + a;
  return out.empty() ? out : " with" + out;
}

void eval_suite(const SuiteArgs& a) {
  check_output(a.markdown, ".md", "--markdown");
  const eval::SuiteDefinition suite = eval::load_suite(
      a.suite.empty() ? eval::default_suite_path() : std::filesystem::path(a.suite));
  const auto chosen = chosen_scenarios(suite.scenarios, a.only);
  const tracking::TrackerOptions tracker = with_tracker_options(a.tracker_options);
  const Scene scene(a.layout, a.head);

  std::vector<eval::SuiteRow> rows;
  // A signal abandons the run before any table is written.
  InterruptScope interrupt;
  for (std::size_t i = 0; i < chosen.size(); ++i) {
    const auto& s = chosen[i];
    Progress progress(fmt::format("[{}/{}] {}", i + 1, chosen.size(), s.name),
                      std::lround(s.seconds * s.fps));
    RowOutput out(a.out, s.name, s.fps);
    rows.push_back(eval::run_scenario(
        s, scene.model, &scene.library, scene.layout,
        [&](long done, long total) {
          interrupt.throw_if_requested();
          progress.update(done, total);
        },
        tracker, out.frames()));
    progress.finish();
    out.finish(rows.back());
  }
  std::fputs(eval::suite_table_text(rows).c_str(), stdout);
  std::printf("\nlost marker-frames by the rule that dropped them\n%s",
              eval::loss_table_text(rows).c_str());
  if (!a.markdown.empty()) {
    const std::string body = fmt::format(
        "Written by `rostro eval suite{} --markdown`{} (rostro {}) on {}.\n\n{}\nLost "
        "marker-frames by the rule that dropped them (tracking::LostReason, kept while the "
        "marker stays lost; every layout marker, visible in the truth or not):\n\n{}",
        a.head.empty() ? "" : " --head " + a.head, options_note(a.tracker_options, {}),
        ROSTRO_VERSION, utc_now(), eval::suite_table_markdown(rows),
        eval::loss_table_markdown(rows));
    eval::replace_markdown_section(a.markdown, "## Suite table", body);
    std::printf("table written to %s (section \"Suite table\")\n", a.markdown.c_str());
  }
}

struct PhotosArgs {
  std::string file, fixtures, layout, markdown, report, only, out;
  std::vector<std::string> tracker_options;  // NAME=VALUE
};

void eval_photos(const PhotosArgs& a) {
  check_output(a.markdown, ".md", "--markdown");
  check_output(a.report, ".json", "--report");
  const std::filesystem::path faces =
      a.fixtures.empty() ? eval::default_faces_dir() : std::filesystem::path(a.fixtures);
  if (std::error_code ec; !std::filesystem::is_directory(faces, ec))
    throw InputError(
        fmt::format("the face photographs folder {} is absent (../shared/fixtures/faces beside the "
                    "repository, or $ROSTRO_SHARED/fixtures/faces; --fixtures DIR names another)",
                    faces.string()));
  const eval::PhotoSuiteDefinition scenes = eval::load_photo_scenes(
      a.file.empty() ? eval::default_photo_scenes_path() : std::filesystem::path(a.file));
  const std::string scenes_file = a.file.empty() ? "data/eval/photo_scenes.json" : a.file;
  const auto chosen = chosen_scenarios(scenes.scenarios, a.only);
  const tracking::TrackerOptions tracker = with_tracker_options(a.tracker_options);
  const tracking::MarkerLayout layout = tracking::load_layout(
      a.layout.empty() ? tracking::default_layout_path() : std::filesystem::path(a.layout));

  std::vector<eval::PhotoRow> rows;
  InterruptScope interrupt;
  for (std::size_t i = 0; i < chosen.size(); ++i) {
    const auto& s = chosen[i];
    Progress progress(fmt::format("[{}/{}] {}", i + 1, chosen.size(), s.name),
                      std::lround(s.scene.seconds * s.scene.fps));
    RowOutput out(a.out, s.name, s.scene.fps);
    rows.push_back(eval::run_photo_scenario(
        s, faces, layout,
        [&](long done, long total) {
          interrupt.throw_if_requested();
          progress.update(done, total);
        },
        tracker, out.frames()));
    progress.finish();
    out.finish(rows.back().suite);
  }
  std::vector<eval::SuiteRow> suite_rows;
  for (const eval::PhotoRow& r : rows) suite_rows.push_back(r.suite);
  std::fputs(eval::suite_table_text(suite_rows).c_str(), stdout);
  std::printf("\n%s", eval::photo_table_text(rows).c_str());
  std::printf("\nlost marker-frames by the rule that dropped them\n%s",
              eval::loss_table_text(suite_rows).c_str());
  if (!a.markdown.empty()) {
    const std::string body = fmt::format(
        "Written by `rostro eval photos{} --markdown`{} (rostro {}) on {}: the scenes of "
        "{}, real photographs of faces (../shared/fixtures/faces) with "
        "the default layout painted on and moved by smooth warps (eval/photo_scene.hpp), "
        "tracked with automatic identification.\n\nOne caution in reading them: the scenes "
        "place the dots from dlib's landmarks on the photograph, and identification looks for "
        "the dots near dlib's landmarks on the frame (tracking/face_prior.hpp). The scenes "
        "move each dot up to 0.12 eye widths off its landmark at random and nudge the brow, "
        "lid and corner dots onto skin, so the two do not coincide, but a face whose dots sit "
        "farther from the landmarks than that has not been tried.\n\n{}\nCentre errors of the dots "
        "and tags over scored observations (visible in the truth, valid in the estimate); "
        "astray: scored observations as far from their own dot as a swap (0.05 of the eye "
        "corners' distance) but nearer it than any other marker's, a name on something that "
        "is no marker; hidden but reported: "
        "valid in the estimate while not visible in the truth; reacquire: the most frames a "
        "marker took, back in view after an occlusion, to be reported within 2 px (- no "
        "occlusion, never: not before the take ended or it was hidden again).\n\n{}\nLost "
        "marker-frames by the rule that dropped them (tracking::LostReason):\n\n{}",
        a.file.empty() ? "" : " --file " + a.file, options_note(a.tracker_options, {}),
        ROSTRO_VERSION, utc_now(), scenes_file, eval::suite_table_markdown(suite_rows),
        eval::photo_table_markdown(rows), eval::loss_table_markdown(suite_rows));
    // One section per scene file, as eval loop's.
    std::string section = "## Photo scenes";
    if (!a.file.empty()) section += ", " + std::filesystem::path(a.file).stem().string();
    eval::replace_markdown_section(a.markdown, section, body);
    std::printf("tables written to %s (section \"%s\")\n", a.markdown.c_str(), section.c_str() + 3);
  }
  if (!a.report.empty()) {
    eval::write_text_file(a.report, eval::photo_report_json(rows, scenes_file, a.tracker_options));
    std::printf("rows written to %s\n", a.report.c_str());
  }
}

struct HeadArgs {
  std::string head, markdown, landmark_model, images;
};

void eval_head(const HeadArgs& a) {
  check_output(a.markdown, ".md", "--markdown");
  const FaceModel model = load_face_model_or_default(a.head);
  const ExpressionLibrary library = ExpressionLibrary::load_default();
  eval::HeadCheckOptions options;
  options.landmark_model = a.landmark_model;
  options.image_dir = a.images;
  if (!a.images.empty()) std::filesystem::create_directories(a.images);
  Progress progress("head check", eval::head_check_renders(options));
  InterruptScope interrupt;
  const eval::HeadCheckResult result =
      eval::check_head(model, library, options, [&](long done, long) {
        interrupt.throw_if_requested();
        progress.update(done);
      });
  progress.finish();
  std::fputs(eval::head_check_table_text(result).c_str(), stdout);
  if (!a.markdown.empty()) {
    const std::string body = fmt::format(
        "Written by `rostro eval head --markdown` (rostro {}) on {}: {} rendered at {}x{}, "
        "neutral and with the six expressions at full intensity, from the front and with the "
        "camera turned 30 degrees either way (eval/head_check.hpp). On each render dlib's HOG "
        "face detector and its 68-point model (trained on photographs) look for a face; each "
        "feature's column is the largest distance of its landmarks from the head's own "
        "feature points as the renderer projects them, in shares of the inter-ocular distance "
        "(the outer eye corners 3.12 to 3.7). Aim (issue 24): a face found on every render; on "
        "the neutral front view every checked landmark within {:.0f} %.\n\n{}",
        ROSTRO_VERSION, utc_now(), a.head.empty() ? std::string("the default head") : a.head,
        options.width, options.height, 100 * options.aim_share,
        eval::head_check_table_markdown(result));
    eval::replace_markdown_section(a.markdown, "## The head as a face detector reads it", body);
    std::printf("table written to %s (section \"The head as a face detector reads it\")\n",
                a.markdown.c_str());
  }
}

struct LoopArgs {
  std::string file, layout, head, markdown, only, out;
  FaceTrackerArgs face;  // --markerless: the head rendered bare, tracked by its landmarks
  std::vector<std::string> tracker_options, solver_options;  // NAME=VALUE
  double truth_noise_px = 0;
};

std::string describe_drive(const eval::LoopScenario& s) {
  std::string out = s.drive == "range_of_motion" ? "the built-in range of motion" : s.drive;
  if (s.seconds > 0) out += fmt::format(", first {:g} s", s.seconds);
  out += fmt::format(", {:g} s neutral lead-in", s.neutral_lead);
  if (s.head.yaw_deg != 0 || s.head.pitch_deg != 0 || s.head.roll_deg != 0)
    out += fmt::format(
        ", head sweeps in FAPs 48-50: yaw +-{:g}, pitch +-{:g}, roll +-{:g} deg, "
        "{:g} s period",
        s.head.yaw_deg, s.head.pitch_deg, s.head.roll_deg, s.head.period_s);
  else
    out += ", head still";
  if (s.head_vertices > 0)
    out += fmt::format(", the head generated at {} vertices", s.head_vertices);
  return out;
}

void eval_loop(const LoopArgs& a) {
  check_output(a.markdown, ".md", "--markdown");
  const eval::LoopDefinition loop = eval::load_closed_loop(
      a.file.empty() ? eval::default_closed_loop_path() : std::filesystem::path(a.file));
  const auto chosen = chosen_scenarios(loop.scenarios, a.only);
  const tracking::TrackerOptions tracker = with_tracker_options(a.tracker_options);
  mapping::SolverOptions solver;
  for (const std::string& s : a.solver_options) mapping::set_solver_option(solver, s);
  solver.validate();
  const Scene scene(a.layout, a.head);

  std::vector<eval::LoopResult> results;
  std::string skipped, scenarios;
  // A signal abandons the run before any table is written (streams of finished scenarios
  // already in --out stay: each is a whole file).
  InterruptScope interrupt;
  for (std::size_t i = 0; i < chosen.size(); ++i) {
    eval::LoopScenario s = chosen[i];
    if (a.face.markerless) s.aim = s.markerless_aim;
    s.truth_noise_px = a.truth_noise_px;
    if (!s.skip_reason.empty()) {
      std::fprintf(stderr, "skipped %s: %s\n", s.name.c_str(), s.skip_reason.c_str());
      skipped += fmt::format("- {} skipped: {}\n", s.name, s.skip_reason);
      continue;
    }
    scenarios += fmt::format("- **{}**: {}.\n", s.name, describe_drive(s));
    Progress progress(fmt::format("[{}/{}] {}", i + 1, chosen.size(), s.name),
                      static_cast<long>(eval::loop_drive(s).frames.size()));
    const auto show = [&](long done, long total) {
      interrupt.throw_if_requested();
      progress.update(done, total);
    };
    if (a.face.markerless)
      results.push_back(eval::run_loop_scenario(
          s, scene.model, &scene.library, [&] { return a.face.make(); }, show, solver));
    else
      results.push_back(eval::run_loop_scenario(s, scene.model, &scene.library, scene.layout, show,
                                                tracker, solver));
    progress.finish();
    if (!a.out.empty()) {
      // The streams behind the tables, for `rostro eval faps --plot`, and the tracks behind
      // them, for `rostro eval tracks`.
      const eval::LoopResult& r = results.back();
      std::filesystem::create_directories(a.out);
      const std::filesystem::path dir(a.out);
      write_fap_stream(dir / (r.name + ".truth.fap"), r.drive);
      tracking::write_tracks(dir / (r.name + ".tracks.csv"), r.tracks);
      tracking::write_tracks(dir / (r.name + ".truth.csv"), r.truth_tracks);
      for (const auto& score : r.scores) {
        if (!score.failure.empty()) continue;  // it wrote nothing
        std::string label = score.label();
        std::replace(label.begin(), label.end(), ' ', '-');
        label.erase(std::remove(label.begin(), label.end(), ','), label.end());
        write_fap_stream(dir / (r.name + "." + label + ".fap"), score.estimate);
      }
    }
  }
  std::printf("%s\n\n", eval::loop_definitions(a.face.markerless).c_str());
  std::fputs(eval::loop_summary_text(results).c_str(), stdout);
  for (const auto& r : results) std::printf("\n%s", eval::loop_fap_table_text(r).c_str());
  if (!a.markdown.empty()) {
    std::string flag = a.face.markerless ? " --markerless" : "";
    if (!a.file.empty()) flag += " --file " + a.file;
    if (!a.head.empty()) flag += " --head " + a.head;
    std::string body = fmt::format(
        "Written by `rostro eval loop{} --markdown`{} (rostro {}) on {}; scenarios in "
        "`{}`. Each clip is rendered in-process (no video "
        "file), {}, and mapped by `mapping::TakeMapper` as "
        "`rostro capture` maps a take without a profile: the actor calibrated from the first "
        "second (the neutral lead-in), the clip's own camera intrinsics, the default "
        "hierarchy.\n\n```sh\nrostro eval loop{}                               # prints the "
        "tables\nrostro eval loop{} --markdown docs/accuracy.md   # and rewrites this "
        "section\nrostro eval loop --only still,turns            # a subset\n```\n\n{}\n\n{}{}\n{}",
        flag, options_note(a.tracker_options, a.solver_options), ROSTRO_VERSION, utc_now(),
        a.file.empty() ? "data/eval/closed_loop.json" : a.file,
        a.face.markerless ? "the head bare, tracked by dlib's 68 landmarks (`--markerless`)"
                          : "tracked with automatic identification of the markers",
        flag, flag, eval::loop_definitions(a.face.markerless), scenarios, skipped,
        eval::loop_summary_markdown(results));
    for (const auto& r : results)
      body += fmt::format("\n### {} ({} frames)\n\n{}", r.title, r.frames,
                          eval::loop_fap_table_markdown(r));
    // One section per tracker and scenario file (the sizes differ between the files).
    std::string section = a.face.markerless ? "## Closed loop: bare face" : "## Closed loop: FAPs";
    if (!a.file.empty()) section += ", " + std::filesystem::path(a.file).stem().string();
    eval::replace_markdown_section(a.markdown, section, body);
    std::printf("tables written to %s (section \"%s\")\n", a.markdown.c_str(), section.c_str() + 3);
  }
}

struct AlignmentArgs {
  std::string markdown, only;
};

void eval_alignment(const AlignmentArgs& a) {
  check_output(a.markdown, ".md", "--markdown");
  std::vector<eval::AlignmentCase> cases = eval::default_alignment_cases();
  if (!a.only.empty()) {
    const auto wanted = split_commas(a.only);
    std::vector<eval::AlignmentCase> chosen;
    for (const std::string& name : wanted) {
      const auto it = std::find_if(cases.begin(), cases.end(),
                                   [&](const eval::AlignmentCase& c) { return c.name == name; });
      if (it == cases.end()) throw InputError("--only: no alignment case '" + name + "'");
      chosen.push_back(*it);
    }
    cases = chosen;
  }
  InterruptScope interrupt;
  std::vector<eval::AlignmentScore> scores;
  Progress progress("alignment", static_cast<long>(cases.size()));
  for (std::size_t i = 0; i < cases.size(); ++i) {
    interrupt.throw_if_requested();
    scores.push_back(eval::score_alignment(cases[i]));
    progress.update(static_cast<long>(i + 1));
  }
  progress.finish();
  const std::string table = eval::alignment_table(scores);
  std::fputs(table.c_str(), stdout);
  if (!a.markdown.empty()) {
    const double refused_above = speech::AlignmentOptions().max_match_ratio;
    const std::string body = fmt::format(
        "Written by `rostro eval alignment --markdown` (rostro {}) on {}: recordings with known "
        "phoneme times, aligned to their transcripts by `rostro speak --audio --text` "
        "(speech/forced_align.hpp). The alignment's reference is the language's espeak-ng voice "
        "at its default rate and pitch, in its male and a female variant (+f3; the one the "
        "recording matches better is kept): no recording below was made by it. Boundaries are "
        "phoneme starts matched by symbol between the aligned and the true sequence; p/b/m "
        "late: true bilabials whose nearest frame with closed lips (25 fps) is more than one "
        "frame from the phoneme; match ratio: the transcript check of speech/forced_align.hpp "
        "(refused above {:.2f}), for the right transcript and for another text in the same "
        "language.\n\n{}",
        ROSTRO_VERSION, utc_now(), refused_above, table);
    eval::replace_markdown_section(a.markdown, "## Speech alignment", body);
    std::printf("table written to %s (section \"Speech alignment\")\n", a.markdown.c_str());
  }
}

}  // namespace

void add_eval_commands(CLI::App& app) {
  CLI::App* eval = app.add_subcommand("eval", "Score tracks and FAP streams against ground truth");
  eval->require_subcommand(1);
  eval->footer("Example:\n  rostro eval tracks --truth truth.csv --tracks take.csv --ced ced.png");

  static TracksArgs t;
  CLI::App* tracks = eval->add_subcommand(
      "tracks", "Marker errors, NME, CED, AUC and failure rate (300-VW), lost frames and swaps");
  tracks
      ->add_option("--truth", t.truth,
                   "ground truth: tracks CSV, or iBUG .pts (a folder, a list .txt, one .pts)")
      ->required();
  tracks->add_option("--tracks", t.tracks, "estimated tracks CSV (rostro track)")->required();
  tracks->add_option("--norm", t.norm, "normalising pair: feature points or marker ids")
      ->capture_default_str();
  tracks->add_option("--report", t.report, "write the JSON report here");
  tracks->add_option("--summary", t.summary, "write a Markdown summary here");
  tracks->add_option("--ced", t.ced, "draw the CED curve as this PNG");
  tracks->add_option("--label", t.label, "legend label of the CED curve (default: file name)");
  tracks->add_option("--threshold", t.threshold, "NME threshold of AUC and failure rate")
      ->capture_default_str();
  tracks
      ->add_option("--swap-threshold", t.swap_threshold,
                   "own error (times the normalising distance) before a swap counts")
      ->capture_default_str();
  tracks
      ->add_option("--match", t.match,
                   "match markers by 'marker' id or 'fp' (auto: fp for .pts truth)")
      ->capture_default_str();
  tracks->add_flag("--lost-is-failure", t.lost_is_failure,
                   "a frame with any lost marker counts as a failure");
  tracks->add_option("--pts-map", t.pts_map,
                     "iBUG index -> marker mapping JSON (default data/eval/ibug68_to_mpeg4.json)");
  tracks->add_option("--pts-first-frame", t.pts_first_frame, "frame number of the first .pts file")
      ->capture_default_str();
  tracks->add_option("--pts-fps", t.pts_fps, "frame rate of a .pts sequence")
      ->capture_default_str();
  tracks->footer(
      "Example:\n  rostro eval tracks --truth clip.truth.csv --tracks clip.tracks.csv \\\n"
      "      --report clip.eval.json --summary clip.eval.md --ced clip.ced.png");
  tracks->callback([] { eval_tracks(t); });

  static FapsArgs f;
  CLI::App* faps = eval->add_subcommand(
      "faps", "Per-FAP RMS error (FAPU and share of range) and correlation; FAP curve plots");
  faps->add_option("--truth", f.truth, "truth FAP stream (.fap, .csv or .json)")->required();
  faps->add_option("--est", f.est, "estimated FAP stream")->required();
  faps->add_option("--report", f.report, "write the JSON report here");
  faps->add_option("--summary", f.summary, "write a Markdown summary here");
  faps->add_option("--plot", f.plot, "draw truth and estimate curves as this PNG");
  faps->add_option("--faps", f.faps,
                   "FAPs to plot, e.g. 3,12,13 (default: the three with the widest range)");
  faps->footer(
      "Example:\n  rostro eval faps --truth clip.fap --est take.fap --plot curves.png --faps "
      "3,12,13");
  faps->callback([] { eval_faps(f); });

  static SuiteArgs su;
  CLI::App* suite = eval->add_subcommand(
      "suite", "The standing accuracy suite: seeded synth clips tracked and scored, one table");
  suite->add_option("--suite", su.suite, "suite definition (default data/eval/suite.json)");
  suite->add_option("--layout", su.layout,
                    "marker layout JSON (default data/layouts/default.json)");
  suite->add_option("--head", su.head,
                    "face model JSON to render, e.g. from rostro head (default: the default "
                    "head)");
  suite->add_option("--only", su.only, "run only these scenarios, e.g. still,turns");
  suite->add_option("--out", su.out,
                    "also write each scenario here as a video and its tracked and exact marker "
                    "tracks (NAME.mp4, NAME.tracks.csv, NAME.truth.csv)");
  suite->add_option("--markdown", su.markdown,
                    "write the table into this Markdown file's \"## Suite table\" section");
  suite->add_option(
      "--tracker-option", su.tracker_options,
      "set a TrackerOptions field, NAME=VALUE (repeatable), e.g. "
      "eyes.max_dot_growth_found=1.3, lower_lip.together=false, dots.max_elongation=4");
  suite->footer(
      "Example:\n  rostro eval suite --markdown docs/accuracy.md\n  rostro eval suite --only mouth "
      "--out suite-clips");
  suite->callback([] { eval_suite(su); });

  static PhotosArgs ph;
  CLI::App* photos = eval->add_subcommand(
      "photos",
      "Photo scenes: real face photographs with the layout painted on, moved by smooth warps, "
      "tracked and scored");
  photos->add_option("--file", ph.file,
                     "photo scenes definition (default data/eval/photo_scenes.json)");
  photos->add_option("--fixtures", ph.fixtures,
                     "folder of the photographs (default ../shared/fixtures/faces)");
  photos->add_option("--layout", ph.layout,
                     "marker layout JSON (default data/layouts/default.json)");
  photos->add_option("--only", ph.only, "run only these scenes, e.g. still,blur");
  photos->add_option("--markdown", ph.markdown,
                     "write the tables into this Markdown file's \"## Photo scenes\" section "
                     "(\"## Photo scenes, NAME\" for --file NAME.json)");
  photos->add_option("--report", ph.report,
                     "also write the rows as JSON for scripts (every figure of the tables)");
  photos->add_option("--out", ph.out,
                     "also write each scene here as a video and its tracked and exact marker "
                     "tracks (NAME.mp4, NAME.tracks.csv, NAME.truth.csv)");
  photos->add_option("--tracker-option", ph.tracker_options,
                     "set a TrackerOptions field, NAME=VALUE (repeatable), e.g. "
                     "dots.max_elongation=4");
  photos->footer(
      "Example:\n  rostro eval photos --only still,blur\n  rostro eval photos --markdown "
      "docs/accuracy.md\n  rostro eval photos --only still --report still.json");
  photos->callback([] { eval_photos(ph); });

  static HeadArgs he;
  CLI::App* head = eval->add_subcommand(
      "head",
      "Does a face detector trained on photographs read the head as a face, its features "
      "where the head has them? (dlib on renders of each expression, front and turned)");
  head->add_option("--head", he.head, "face model JSON (default: the default head)");
  head->add_option("--landmark-model", he.landmark_model,
                   "dlib 68-point model (default /usr/share/dlib/"
                   "shape_predictor_68_face_landmarks.dat)");
  head->add_option("--images", he.images,
                   "write each render with dlib's landmarks (green), the head's feature points "
                   "(red) and the face box (blue) into this folder");
  head->add_option("--markdown", he.markdown,
                   "write the table into this Markdown file's \"## The head as a face detector "
                   "reads it\" section");
  head->footer(
      "Example:\n  rostro eval head\n  rostro eval head --images head-check\n  rostro eval "
      "head --markdown docs/accuracy.md");
  head->callback([] { eval_head(he); });

  static LoopArgs lo;
  CLI::App* loop = eval->add_subcommand(
      "loop",
      "Closed loop: synth clips driven by known FAPs, tracked, mapped (ceres, seed2d, ceres on "
      "exact tracks) and scored per FAP");
  loop->add_option("--file", lo.file,
                   "closed-loop definition (default data/eval/closed_loop.json)");
  loop->add_option("--layout", lo.layout, "marker layout JSON (default data/layouts/default.json)");
  loop->add_option("--head", lo.head,
                   "face model JSON to render, e.g. from rostro head (default: the default head)");
  loop->add_flag("--markerless", lo.face.markerless,
                 "render the head bare and track it by its 68 landmarks (rostro capture "
                 "--markerless)");
  loop->add_option("--landmark-model", lo.face.landmarks.model,
                   "dlib 68-point model with --markerless");
  loop->add_option("--only", lo.only, "run only these scenarios, e.g. still,turns");
  loop->add_option("--out", lo.out,
                   "also write each scenario's truth and mapped streams here as .fap "
                   "(NAME.truth.fap, NAME.ceres.fap, ...) and its tracked and exact marker "
                   "tracks (NAME.tracks.csv, NAME.truth.csv)");
  CLI::Option* loop_markdown = loop->add_option(
      "--markdown", lo.markdown,
      "write the tables into this Markdown file's \"## Closed loop: FAPs\" section");
  loop->add_option("--truth-noise", lo.truth_noise_px,
                   "also fit the exact tracks with Gaussian noise of this sigma (px) on each "
                   "coordinate: how precise tracks must be for the aim (not with --markdown)")
      ->check(CLI::PositiveNumber)
      ->excludes(loop_markdown);
  loop->add_option(
      "--tracker-option", lo.tracker_options,
      "set a TrackerOptions field, NAME=VALUE (repeatable), e.g. eyes.max_dot_growth_found=1.3");
  loop->add_option("--solver-option", lo.solver_options,
                   "set a SolverOptions field for both Ceres fits, NAME=VALUE (repeatable), e.g. "
                   "pose_prior_weight=0");
  loop->footer(
      "Drives under shared: come from $ROSTRO_SHARED (default ../shared); absent ones are "
      "skipped.\n\nExample:\n"
      "  rostro eval loop --only still,turns\n"
      "  rostro eval loop --markdown docs/accuracy.md\n"
      "  rostro eval loop --markerless --only still,joy\n"
      "  rostro eval loop --markerless --only still --truth-noise 0.5\n"
      "  rostro head -o head20k --vertices 20000 && rostro eval loop --head head20k/head.json "
      "--only still");
  loop->callback([] { eval_loop(lo); });

  static AlignmentArgs al;
  CLI::App* alignment = eval->add_subcommand(
      "alignment",
      "Speech alignment: recordings with known phoneme times (other espeak-ng voices, rates, "
      "noise; flite) aligned to their transcripts and scored");
  alignment->add_option("--only", al.only, "run only these cases, e.g. es_female_slow,en_female");
  alignment->add_option("--markdown", al.markdown,
                        "write the table into this Markdown file's \"## Speech alignment\" "
                        "section");
  alignment->footer(
      "Example:\n  rostro eval alignment --only es_female_slow\n  rostro eval alignment "
      "--markdown docs/accuracy.md");
  alignment->callback([] { eval_alignment(al); });
}

}  // namespace rostro::app
