#include "eval/closed_loop.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <set>

#include "eval/scenario_file.hpp"
#include "facecore/data_path.hpp"
#include "facecore/error.hpp"
#include "facecore/fap_io.hpp"
#include "facecore/head_generator.hpp"
#include "facecore/json_file.hpp"
#include "mapping/marker_model.hpp"
#include "mapping/take_mapper.hpp"
#include "render/frame_sink.hpp"
#include "tracking/marker_tracker.hpp"
#include "tracking/name_corrections.hpp"
#include "tracking/start_backfill.hpp"

namespace rostro::eval {
namespace {

using nlohmann::json;

constexpr int kHeadPitch = 48, kHeadRoll = 50;

// Hands each rendered frame to a function (here: the tracker), keeping no image.
class CallbackSink : public render::FrameSink {
 public:
  explicit CallbackSink(std::function<void(const cv::Mat&)> f) : f_(std::move(f)) {}
  void write(const cv::Mat& bgr) override {
    f_(bgr);
    ++count_;
  }
  void finish() override {}
  long frames_written() const override { return count_; }

 private:
  std::function<void(const cv::Mat&)> f_;
  long count_ = 0;
};

LoopScenario parse_scenario(const json& j, const json& defaults, const std::string& where) {
  static const std::set<std::string> known = {
      "name",        "title",        "drive",          "fps",           "seconds",
      "seed",        "neutral_lead", "head_yaw",       "head_pitch",    "head_roll",
      "head_period", "aim",          "markerless_aim", "head_vertices", "camera_elevation",
      "size"};
  if (!j.is_object()) throw InputError(where + ": a scenario should be an object");
  for (const auto& [key, value] : j.items())
    if (!known.count(key)) throw InputError(where + ": unknown key '" + key + "'");
  LoopScenario s;
  if (!j.contains("name") || !j["name"].is_string() || j["name"].get<std::string>().empty())
    throw InputError(where + ": 'name' should be a non-empty string");
  s.name = j["name"].get<std::string>();
  const std::string at = where + " (" + s.name + ")";
  auto num = [&](const char* key, double fallback) {
    const json* v = j.contains(key) ? &j[key] : defaults.contains(key) ? &defaults[key] : nullptr;
    if (v == nullptr) return fallback;
    if (!v->is_number())
      throw InputError((j.contains(key) ? at : where) + ": '" + key + "' should be a number");
    return v->get<double>();
  };
  auto text = [&](const char* key, const std::string& fallback) {
    if (!j.contains(key)) return fallback;
    if (!j[key].is_string()) throw InputError(at + ": '" + key + "' should be a string");
    return j[key].get<std::string>();
  };
  s.title = text("title", s.name);
  s.drive = text("drive", "range_of_motion");
  s.fps = num("fps", 25);
  s.seconds = num("seconds", 0);
  s.neutral_lead = num("neutral_lead", 1.0);
  s.calibration_seconds = num("calibration_seconds", 1.0);
  s.head.yaw_deg = num("head_yaw", 0);
  s.head.pitch_deg = num("head_pitch", 0);
  s.head.roll_deg = num("head_roll", 0);
  s.head.period_s = num("head_period", 4.0);
  const bool turns = s.head.yaw_deg != 0 || s.head.pitch_deg != 0 || s.head.roll_deg != 0;
  s.aim = num("aim", turns ? 0.08 : 0.05);
  s.markerless_aim = num("markerless_aim", turns ? 0.15 : 0.10);
  if (!(s.fps > 0)) throw InputError(at + ": 'fps' should be positive");
  if (s.seconds < 0) throw InputError(at + ": 'seconds' should not be negative");
  if (s.neutral_lead < 0) throw InputError(at + ": 'neutral_lead' should not be negative");
  if (!(s.calibration_seconds > 0))
    throw InputError(where + ": 'calibration_seconds' should be positive");
  if (!(s.head.period_s > 0)) throw InputError(at + ": 'head_period' should be positive");
  if (!(s.aim > 0 && s.aim < 1)) throw InputError(at + ": 'aim' should be a share in (0, 1)");
  if (!(s.markerless_aim > 0 && s.markerless_aim < 1))
    throw InputError(at + ": 'markerless_aim' should be a share in (0, 1)");
  const double vertices = num("head_vertices", 0);
  if (vertices != 0 && !(vertices >= kMinHeadVertices && vertices <= 1e6))
    throw InputError(at + ": 'head_vertices' should be 0 (the head given) or from " +
                     std::to_string(kMinHeadVertices) + " to 1000000");
  s.head_vertices = static_cast<int>(vertices);
  s.synth.seed = static_cast<unsigned>(num("seed", 1));
  s.synth.elevation_deg = num("camera_elevation", 0);
  if (!(std::abs(s.synth.elevation_deg) <= kMaxElevationDeg))
    throw InputError(at + fmt::format(": 'camera_elevation' should be within -{0:g}..{0:g} degrees",
                                      kMaxElevationDeg));
  if (j.contains("size") || defaults.contains("size")) {  // the scenario's, else the file's
    const json& size = j.contains("size") ? j["size"] : defaults["size"];
    if (!size.is_array() || size.size() != 2 || !size[0].is_number_integer() ||
        !size[1].is_number_integer() || size[0].get<int>() < 16 || size[1].get<int>() < 16)
      throw InputError((j.contains("size") ? at : where) +
                       ": 'size' should be [width, height] in pixels");
    s.synth.width = size[0].get<int>();
    s.synth.height = size[1].get<int>();
  }

  const std::string shared_prefix = "shared:";
  if (s.drive == "range_of_motion") {
    s.fap.clear();
  } else if (s.drive.rfind(shared_prefix, 0) == 0) {
    s.fap = shared_dir() / s.drive.substr(shared_prefix.size());
    if (!std::filesystem::is_regular_file(s.fap))
      s.skip_reason = s.fap.string() +
                      " is absent (the shared folder: $ROSTRO_SHARED, else "
                      "../shared beside the repository)";
  } else {
    try {
      s.fap = data_file(s.drive);
    } catch (const InputError&) {
      throw InputError(at + ": 'drive' " + s.drive +
                       ": expected range_of_motion, shared:PATH or a file under " +
                       data_dir().string());
    }
  }
  return s;
}

std::string pct(double share) {
  return fmt::format("{:.1f}", 100.0 * share);
}

std::string fap_name(int id) {
  return std::string(fap_info(id).name);
}

std::string worst_label(const LoopScore& s) {
  return s.worst_fap ? fmt::format("{} ({})", fap_name(s.worst_fap), s.worst_fap) : "-";
}

std::string met_label(const LoopScore& s) {
  if (!s.failure.empty()) return "failed: " + s.failure;
  if (s.scored == 0) return "no FAP scored";
  std::string out = s.met ? "met" : "not met";
  if (!s.not_output.empty()) out += fmt::format(" ({} not output)", s.not_output.size());
  return out;
}

// Frames of `stream` that set FAP `id`, and its range over them (0 when it never moves).
struct Extent {
  long frames = 0;
  double range = 0;
};
Extent extent(const FapStream& stream, int id) {
  Extent x;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const FapFrame& f : stream.frames)
    if (f.has(id)) {
      ++x.frames;
      lo = std::min(lo, f.get(id));
      hi = std::max(hi, f.get(id));
    }
  x.range = x.frames ? hi - lo : 0.0;
  return x;
}

// Per FAP: "RMS (share %)", with the frames compared when the method skipped some of the
// truth's, or a dash when the method does not write it.
std::string fap_cell(const LoopResult& r, const LoopScore& s, int id) {
  const FapError* e = s.find(id);
  if (e == nullptr) return "-";
  std::string out = e->rms_share_of_range
                        ? fmt::format("{:.1f} ({}%)", e->rms, pct(*e->rms_share_of_range))
                        : fmt::format("{:.1f}", e->rms);
  const long truth_frames = extent(r.drive, id).frames;
  if (e->frames < truth_frames) out += fmt::format(" [{}/{}]", e->frames, truth_frames);
  return out;
}

// The exact tracks with independent Gaussian noise of `sigma` pixels on each coordinate of
// every valid observation: a tracker's error without its bias.
std::vector<tracking::TrackedFrame> with_noise(std::vector<tracking::TrackedFrame> tracks,
                                               double sigma, unsigned seed) {
  std::mt19937 random(seed);
  std::normal_distribution<double> noise(0.0, sigma);
  for (tracking::TrackedFrame& f : tracks)
    for (tracking::MarkerObservation& o : f.markers)
      if (o.valid) o.position += cv::Point2d(noise(random), noise(random));
  return tracks;
}

}  // namespace

std::filesystem::path default_closed_loop_path() {
  return data_file("eval/closed_loop.json");
}

std::filesystem::path shared_dir() {
  if (const char* env = std::getenv("ROSTRO_SHARED"); env != nullptr && *env != '\0') return env;
  return (data_dir() / ".." / ".." / "shared").lexically_normal();
}

LoopDefinition load_closed_loop(const std::filesystem::path& path) {
  const json j = read_json_file(path, "the closed-loop file");
  LoopDefinition d;
  d.scenarios =
      parse_scenario_list<LoopScenario>(j, path,
                                        {"size", "seed", "fps", "neutral_lead",
                                         "calibration_seconds", "head_period", "head_vertices"},
                                        parse_scenario);
  d.description = j.value("description", "");
  return d;
}

FapStream loop_drive(const LoopScenario& s) {
  FapStream drive = s.fap.empty() ? range_of_motion(s.fps) : read_fap_stream(s.fap);
  if (s.seconds > 0) {
    const auto keep = static_cast<std::size_t>(std::lround(s.seconds * drive.header.fps));
    if (keep < drive.frames.size()) drive.frames.resize(keep);
  }
  prepend_neutral(drive, s.neutral_lead);  // also renumbers the frames from 0
  HeadSweeps head = s.head;
  head.start_s = s.neutral_lead;
  add_head_sweeps(drive, head);
  drive.header.frame_count = static_cast<long>(drive.frames.size());
  return drive;
}

std::string method_label(LoopMethod m) {
  switch (m) {
    case LoopMethod::Ceres:
      return "ceres";
    case LoopMethod::Seed2d:
      return "seed2d";
    case LoopMethod::CeresOnTruth:
      return "ceres, exact tracks";
    case LoopMethod::CeresOnNoisyTruth:
      return "ceres, noisy exact tracks";
  }
  return "?";
}

const FapError* LoopScore::find(int fap) const {
  for (const FapError& e : eval.faps)
    if (e.fap == fap) return &e;
  return nullptr;
}

std::string LoopScore::label() const {
  if (method == LoopMethod::CeresOnNoisyTruth)
    return fmt::format("ceres, exact tracks + {:g} px noise", noise_px);
  return method_label(method);
}

const LoopScore& LoopResult::score(LoopMethod m) const {
  for (const LoopScore& s : scores)
    if (s.method == m) return s;
  throw std::out_of_range("closed loop: no score for " + method_label(m));
}

LoopResult run_loop_scenario(const LoopScenario& s, const FaceModel& model,
                             const ExpressionLibrary* library, const tracking::MarkerLayout& layout,
                             const LoopProgress& progress,
                             const tracking::TrackerOptions& tracker_options,
                             const mapping::SolverOptions& solver_options) {
  return run_loop_scenario(
      s, model, library,
      [&] { return std::make_unique<tracking::MarkerTracker>(layout, tracker_options); }, progress,
      solver_options);
}

LoopResult run_loop_scenario(const LoopScenario& s, const FaceModel& model,
                             const ExpressionLibrary* library, const TrackerFactory& make_tracker,
                             const LoopProgress& progress,
                             const mapping::SolverOptions& solver_options) {
  // A scenario may name its own head: the generated one at that density.
  const std::optional<FaceModel> generated =
      s.head_vertices > 0 ? std::optional(generate_head(HeadOptions{s.head_vertices}))
                          : std::nullopt;
  const FaceModel& head = generated ? *generated : model;
  const FapStream drive = loop_drive(s);
  const double fps = drive.header.fps;
  const long total = static_cast<long>(drive.frames.size());

  const std::unique_ptr<tracking::FaceTracker> tracker = make_tracker();
  const tracking::MarkerLayout& layout = tracker->layout();
  SynthOptions o = s.synth;
  o.dot_diameter_mm = layout.dot_diameter_mm;
  o.dark_dots = layout.polarity == tracking::DotPolarity::Dark;
  const auto markers = place_markers(head, layout);
  std::vector<tracking::TrackedFrame> tracked;
  tracking::StartBackfill backfill(*tracker, tracker->correction_horizon());
  CallbackSink sink([&](const cv::Mat& bgr) {
    const auto i = static_cast<std::size_t>(tracked.size());
    tracking::TrackedFrame now =
        tracker->track(bgr, drive.frames[i].index, static_cast<double>(i) / fps);
    backfill.take(now, tracked, bgr);
    tracking::append_corrected(tracked, std::move(now));
  });
  const SynthResult truth = synthesize(head, library, markers, drive, o, sink, [&](long done) {
    if (progress) progress(done, total);
  });

  LoopResult r;
  r.name = s.name;
  r.title = s.title;
  r.frames = total;
  r.aim = s.aim;
  const long calibration_frames = std::max(1L, std::lround(s.calibration_seconds * fps));
  // The profile the tracked FAPs are read from: the Ceres fit's on the tracker's tracks, or
  // on the exact tracks where the tracker's calibration failed.
  std::optional<calib::ActorProfile> ceres_profile;
  mapping::MapperOptions ceres_options;
  std::vector<LoopMethod> methods(kLoopMethods.begin(), kLoopMethods.end());
  if (s.truth_noise_px > 0) methods.push_back(LoopMethod::CeresOnNoisyTruth);
  // The head the clip shows is the one the fit models: on a head other than the default one
  // the loop measures the tracking, not how two heads' deformations differ.
  const auto prior_head = std::make_shared<const FaceModel>(head);
  for (LoopMethod m : methods) {
    mapping::MapperOptions options;
    options.method = m == LoopMethod::Seed2d ? mapping::Method::Seed2d : mapping::Method::Ceres;
    options.solver = solver_options;
    options.hierarchy = mapping::default_hierarchy();  // as `rostro capture` maps by default
    mapping::TakeMapper take(layout, options, truth.intrinsics, std::nullopt, calibration_frames);
    take.calibrate_on(prior_head);
    LoopScore score;
    score.method = m;
    if (m == LoopMethod::CeresOnNoisyTruth) score.noise_px = s.truth_noise_px;
    FapStream est;
    est.header.name = "closed loop " + s.name + " " + score.label();
    est.header.fps = fps;
    std::vector<tracking::TrackedFrame> noisy;
    if (m == LoopMethod::CeresOnNoisyTruth)
      noisy = with_noise(truth.truth, s.truth_noise_px, s.synth.seed);
    const auto& input = m == LoopMethod::CeresOnTruth        ? truth.truth
                        : m == LoopMethod::CeresOnNoisyTruth ? noisy
                                                             : tracked;
    try {
      for (const auto& f : input)
        for (FapFrame& out : take.push(f)) est.frames.push_back(std::move(out));
      for (FapFrame& out : take.finish()) est.frames.push_back(std::move(out));
    } catch (const InputError& e) {
      score.failure = e.what();
      r.scores.push_back(std::move(score));
      continue;
    }
    est.header.frame_count = static_cast<long>(est.frames.size());

    score.calibration_frames = take.calibration_frames_used();
    score.fitted_frames = std::count_if(est.frames.begin(), est.frames.end(),
                                        [](const FapFrame& f) { return f.mask.any(); });
    score.eval = evaluate_faps(drive, est);
    score.estimate = std::move(est);
    if (m == LoopMethod::Ceres || (m == LoopMethod::CeresOnTruth && !ceres_profile)) {
      ceres_profile = *take.profile();
      ceres_options = options;
    }
    r.scores.push_back(std::move(score));
  }
  if (!ceres_profile)
    throw InputError("closed loop " + s.name +
                     ": no Ceres fit calibrated the actor: " + r.score(LoopMethod::Ceres).failure);

  // The tracked FAPs: what the Ceres fit measures with this clip's profile, built with the
  // options make_fap_mapper() gives it, and moved by the drive.
  mapping::MarkerModelOptions model_options = ceres_options.solver.model;
  if (ceres_options.hierarchy) model_options.derived_rules = ceres_options.hierarchy->rules;
  std::set<int> measured;
  for (int id : mapping::build_marker_model(*ceres_profile, model_options).faps)
    measured.insert(id);
  if (ceres_options.solver.head_faps)
    for (int id = kHeadPitch; id <= kHeadRoll; ++id) measured.insert(id);
  for (int id : measured)
    if (extent(drive, id).range > 0) r.tracked.push_back(id);
  for (int id = 3; id <= kFapCount; ++id)
    if (!measured.count(id) && extent(drive, id).range > 0) r.driven_untracked.push_back(id);
  r.drive = drive;
  r.tracks = std::move(tracked);
  r.truth_tracks = truth.truth;

  for (LoopScore& score : r.scores) {
    if (!score.failure.empty()) {
      score.not_output = r.tracked;
      continue;
    }
    double sum = 0;
    for (int id : r.tracked) {
      const FapError* e = score.find(id);
      if (e == nullptr) {
        score.not_output.push_back(id);
        continue;
      }
      // Constant over the compared frames (written only where the truth rests): the share
      // of its whole range instead.
      const double share = e->rms_share_of_range.value_or(e->rms / extent(drive, id).range);
      score.coverage = std::min(score.coverage, static_cast<double>(e->frames) /
                                                    static_cast<double>(extent(drive, id).frames));
      sum += share;
      ++score.scored;
      if (share >= score.max_share) {
        score.max_share = share;
        score.worst_fap = id;
      }
    }
    score.mean_share = score.scored ? sum / score.scored : 0.0;
    score.met = score.scored > 0 && score.not_output.empty() && score.max_share <= s.aim;
  }
  return r;
}

std::string loop_untracked_line(const LoopResult& r) {
  if (r.driven_untracked.empty()) return "";
  const LoopScore& ceres = r.score(LoopMethod::Ceres);
  std::string out = "Driven, not tracked (ceres RMS share of range, through the hierarchy):";
  for (int id : r.driven_untracked) {
    const FapError* e = ceres.find(id);
    out += fmt::format(" {} ({}) {};", fap_name(id), id,
                       e && e->rms_share_of_range ? pct(*e->rms_share_of_range) + "%"
                                                  : std::string("not written"));
  }
  out.back() = '.';
  return out;
}

std::string loop_definitions(bool markerless) {
  return "Tracked FAPs: the FAPs the Ceres fit measures directly with the clip's calibrated "
         "profile (its marker model's FAPs and the head rotation 48-50 from its pose; not the "
         "FAPs the hierarchy derives), of which those with a non-zero range in the driving "
         "stream. Per FAP: RMS error in the FAP's unit over the frames both streams set (the "
         "neutral lead-in sets none, so it is not scored), and "
         "as a share of the truth's range (max - min) over those frames. Aim: every tracked "
         "FAP within " +
         std::string(markerless ? "10 % of its range with a still head, 15 % with head turns "
                                  "(a bare face, issue 17)"
                                : "5 % of its range with a still head, 8 % with head turns") +
         ". A method that never writes a tracked FAP (seed2d has no head pose) does not meet the "
         "aim. Coverage: the least share of a tracked FAP's truth frames the method wrote it in "
         "(a FAP is not written while its marker is lost; [n/N] in the tables marks such FAPs, "
         "whose RMS is over the n frames only).";
}

std::string loop_summary_text(const std::vector<LoopResult>& results) {
  std::string out =
      fmt::format("{:<10} {:<34} {:>6} {:>7} {:>7}  {:<30} {:>8} {:>4}  {}\n", "scenario", "method",
                  "FAPs", "mean %", "max %", "worst FAP", "coverage", "aim", "");
  for (const LoopResult& r : results)
    for (const LoopScore& s : r.scores)
      out += fmt::format("{:<10} {:<34} {:>6} {:>7} {:>7}  {:<30} {:>7}% {:>3.0f}%  {}\n", r.name,
                         s.label(), fmt::format("{}/{}", s.scored, r.tracked.size()),
                         pct(s.mean_share), pct(s.max_share), worst_label(s), pct(s.coverage),
                         100 * r.aim, met_label(s));
  return out;
}

std::string loop_summary_markdown(const std::vector<LoopResult>& results) {
  std::string out =
      "| scenario | frames | method | tracked FAPs scored | mean % of range | max % of range | "
      "worst FAP | coverage | aim | |\n|---|---:|---|---:|---:|---:|---|---:|---:|---|\n";
  for (const LoopResult& r : results)
    for (const LoopScore& s : r.scores)
      out +=
          fmt::format("| {} | {} | {} | {} / {} | {} | {} | {} | {} % | {:.0f} % | {} |\n", r.title,
                      r.frames, s.label(), s.scored, r.tracked.size(), pct(s.mean_share),
                      pct(s.max_share), worst_label(s), pct(s.coverage), 100 * r.aim, met_label(s));
  return out;
}

std::string loop_fap_table_text(const LoopResult& r) {
  std::string out =
      fmt::format("{} ({} frames): RMS in the FAP's unit (share of range)\n", r.title, r.frames);
  out += fmt::format("{:<4} {:<26} {:<5} {:>8}", "FAP", "name", "unit", "range");
  for (const LoopScore& s : r.scores) out += fmt::format(" {:>28}", s.label());
  out += "\n";
  for (int id : r.tracked) {
    out += fmt::format("{:<4} {:<26} {:<5} {:>8}", id, fap_name(id),
                       std::string(unit_name(fap_info(id).unit)),
                       fmt::format("{:.0f}", extent(r.drive, id).range));
    for (const LoopScore& s : r.scores) out += fmt::format(" {:>28}", fap_cell(r, s, id));
    out += "\n";
  }
  if (const std::string u = loop_untracked_line(r); !u.empty()) out += u + "\n";
  return out;
}

std::string loop_fap_table_markdown(const LoopResult& r) {
  std::string out = "| FAP | name | unit | truth range (all frames) |";
  std::string rule = "|---:|---|---|---:|";
  for (const LoopScore& s : r.scores) {
    out += " " + s.label() + " RMS (% of range) |";
    rule += "---:|";
  }
  out += "\n" + rule + "\n";
  for (int id : r.tracked) {
    out += fmt::format("| {} | {} | {} | {} |", id, fap_name(id),
                       std::string(unit_name(fap_info(id).unit)),
                       fmt::format("{:.0f}", extent(r.drive, id).range));
    for (const LoopScore& s : r.scores) {
      const FapError* e = s.find(id);
      const bool over = e && e->rms_share_of_range && *e->rms_share_of_range > r.aim;
      out += " " + (over ? "**" + fap_cell(r, s, id) + "**" : fap_cell(r, s, id)) + " |";
    }
    out += "\n";
  }
  if (const std::string u = loop_untracked_line(r); !u.empty()) out += "\n" + u + "\n";
  return out;
}

}  // namespace rostro::eval
