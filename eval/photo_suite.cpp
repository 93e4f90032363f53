#include "eval/photo_suite.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <set>

#include "eval/scenario_file.hpp"
#include "eval/tracked_take.hpp"
#include "facecore/data_path.hpp"
#include "facecore/error.hpp"
#include "facecore/json_file.hpp"

namespace rostro::eval {
namespace {

using nlohmann::json;

// How near its truth (px) a marker back in view must be reported to count as reacquired.
constexpr double kReacquiredPx = 2;

PhotoScenario parse_photo_scenario(const json& j, const json& defaults, const std::string& where) {
  static const std::set<std::string> known = {
      "name",          "title",      "photo",    "face",   "size", "face_px",
      "dot_px",        "fps",        "seconds",  "motion", "seed", "first_blur_px",
      "enter_seconds", "brightness", "gradient", "noise",  "hand", "placement_jitter"};
  if (!j.is_object()) throw InputError(where + ": a scenario should be an object");
  for (const auto& [key, value] : j.items())
    if (!known.count(key)) throw InputError(where + ": unknown key '" + key + "'");
  auto value = [&](const char* key) -> const json* {
    if (j.contains(key)) return &j[key];
    if (defaults.contains(key)) return &defaults[key];
    return nullptr;
  };
  auto num = [&](const char* key, double fallback) {
    const json* v = value(key);
    if (v == nullptr) return fallback;
    if (!v->is_number()) throw InputError(where + ": '" + key + "' should be a number");
    return v->get<double>();
  };
  PhotoScenario s;
  s.name = j.value("name", "");
  if (s.name.empty()) throw InputError(where + ": a scenario needs a name");
  s.title = j.value("title", s.name);
  PhotoSceneOptions& o = s.scene;
  const std::string photo = j.value("photo", "");
  if (photo.empty()) throw InputError(where + " (" + s.name + "): a scenario needs a photo");
  o.photo = photo;
  if (const json* size = value("size")) {
    if (!size->is_array() || size->size() != 2)
      throw InputError(where + " (" + s.name + "): 'size' should be [width, height]");
    o.size = {size->at(0).get<int>(), size->at(1).get<int>()};
  }
  o.face = static_cast<int>(num("face", 0));
  o.face_px = num("face_px", o.face_px);
  o.dot_px = num("dot_px", o.dot_px);
  o.fps = num("fps", o.fps);
  o.seconds = num("seconds", o.seconds);
  o.motion = j.value("motion", o.motion);
  o.seed = static_cast<unsigned>(num("seed", 1));
  o.first_blur_px = num("first_blur_px", 0);
  o.enter_seconds = num("enter_seconds", 0);
  o.brightness = num("brightness", 1);
  o.gradient = num("gradient", 0);
  o.noise = num("noise", o.noise);
  o.hand = j.value("hand", false);
  o.placement_jitter = num("placement_jitter", o.placement_jitter);
  if (!(o.placement_jitter >= 0))
    throw InputError(where + " (" + s.name + "): 'placement_jitter' should not be negative");
  if (!(o.fps > 0) || !(o.seconds > 0))
    throw InputError(where + " (" + s.name + "): fps and seconds should be positive");
  return s;
}

std::string reacquire_text(const PhotoRow& r) {
  if (r.occlusions == 0) return "-";
  return r.worst_reacquire < 0 ? "never" : std::to_string(r.worst_reacquire);
}

}  // namespace

std::filesystem::path default_photo_scenes_path() {
  return data_file("eval/photo_scenes.json");
}

std::filesystem::path default_faces_dir() {
  if (const char* env = std::getenv("ROSTRO_SHARED"); env != nullptr && *env != '\0')
    return std::filesystem::path(env) / "fixtures" / "faces";
  return (data_dir() / ".." / ".." / "shared" / "fixtures" / "faces").lexically_normal();
}

PhotoSuiteDefinition load_photo_scenes(const std::filesystem::path& path) {
  const json j = read_json_file(path, "the photo scenes file");
  PhotoSuiteDefinition d;
  d.scenarios = parse_scenario_list<PhotoScenario>(
      j, path, {"seconds", "fps", "size", "noise", "placement_jitter"}, parse_photo_scenario);
  d.description = j.value("description", "");
  return d;
}

void count_hidden_and_reacquire(const std::vector<tracking::TrackedFrame>& truth,
                                const std::vector<tracking::TrackedFrame>& estimate,
                                PhotoRow& row) {
  const std::size_t frames = std::min(truth.size(), estimate.size());
  row.hidden_reported = 0;
  row.worst_reacquire = 0;
  row.occlusions = 0;
  if (frames == 0) return;
  const std::size_t markers = truth[0].markers.size();
  for (std::size_t m = 0; m < markers; ++m) {
    bool seen = false;      // visible in the truth at some earlier frame
    bool occluded = false;  // hidden since then
    long back_at = -1;      // the frame it came back into view, while not yet reacquired
    for (std::size_t f = 0; f < frames; ++f) {
      const tracking::MarkerObservation& t = truth[f].markers[m];
      const tracking::MarkerObservation* e = nullptr;
      for (const tracking::MarkerObservation& o : estimate[f].markers)
        if (o.marker == t.marker) e = &o;
      const bool reported = e != nullptr && e->valid;
      if (!t.valid) {
        if (reported) ++row.hidden_reported;
        if (back_at >= 0) row.worst_reacquire = -1;  // hidden again before it was back
        back_at = -1;
        occluded = seen;
        continue;
      }
      if (occluded) {
        back_at = static_cast<long>(f);
        ++row.occlusions;
        occluded = false;
      }
      seen = true;
      if (back_at >= 0 && reported &&
          std::hypot(e->position.x - t.position.x, e->position.y - t.position.y) <= kReacquiredPx) {
        if (row.worst_reacquire >= 0)
          row.worst_reacquire = std::max(row.worst_reacquire, static_cast<long>(f) - back_at);
        back_at = -1;
      }
    }
    if (back_at >= 0) row.worst_reacquire = -1;  // the take ended before it was back
  }
}

PhotoRow run_photo_scenario(const PhotoScenario& s, const std::filesystem::path& faces,
                            const tracking::MarkerLayout& layout,
                            const std::function<void(long, long)>& progress,
                            const tracking::TrackerOptions& tracker_options,
                            const PhotoFrameSink& frames) {
  PhotoSceneOptions o = s.scene;
  o.photo = faces / s.scene.photo;
  tracking::MarkerTracker tracker(layout, tracker_options);
  TrackedTake take(tracker, o.fps);
  const long total = std::max(1L, std::lround(o.seconds * o.fps));
  const PhotoSceneResult scene = render_photo_scene(
      o, layout,
      [&](const cv::Mat& bgr) {
        if (frames) frames(bgr);
        take.add(bgr);
      },
      [&](long done) {
        if (progress) progress(done, total);
      });
  PhotoRow row;
  row.suite.lost_by = take.lost_by();
  row.suite.name = s.name;
  row.suite.title = s.title;
  row.suite.frames = static_cast<long>(take.frames().size());
  row.suite.result = evaluate_tracks(scene.truth, take.frames());
  count_hidden_and_reacquire(scene.truth, take.frames(), row);
  row.suite.truth = scene.truth;
  row.suite.tracks = take.take_frames();
  return row;
}

std::string photo_table_markdown(const std::vector<PhotoRow>& rows) {
  std::string out =
      "| scene | median px | p95 px | swaps (events) | astray | lost / visible | "
      "hidden but reported | worst reacquire (frames) "
      "|\n|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const PhotoRow& r : rows) {
    const TrackEvalResult& e = r.suite.result;
    out += fmt::format("| {} | {:.2f} | {:.2f} | {} ({}) | {} | {} / {} | {} | {} |\n",
                       r.suite.title, e.error_px.median, e.error_px.p95, e.swap_observations,
                       e.swap_events, e.astray_observations, e.lost_observations,
                       e.lost_observations + e.scored_observations, r.hidden_reported,
                       reacquire_text(r));
  }
  return out;
}

std::string photo_table_text(const std::vector<PhotoRow>& rows) {
  std::string out =
      fmt::format("{:<14} {:>9} {:>9} {:>14} {:>7} {:>14} {:>8} {:>10}\n", "scene", "median px",
                  "p95 px", "swaps (events)", "astray", "lost/visible", "hidden+", "reacquire");
  for (const PhotoRow& r : rows) {
    const TrackEvalResult& e = r.suite.result;
    out += fmt::format(
        "{:<14} {:>9.2f} {:>9.2f} {:>14} {:>7} {:>14} {:>8} {:>10}\n", r.suite.name,
        e.error_px.median, e.error_px.p95,
        fmt::format("{} ({})", e.swap_observations, e.swap_events), e.astray_observations,
        fmt::format("{}/{}", e.lost_observations, e.lost_observations + e.scored_observations),
        r.hidden_reported, reacquire_text(r));
  }
  return out;
}

}  // namespace rostro::eval
