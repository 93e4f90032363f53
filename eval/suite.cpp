#include "eval/suite.hpp"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "eval/scenario_file.hpp"
#include "eval/tracked_take.hpp"
#include "facecore/atomic_file.hpp"
#include "facecore/data_path.hpp"
#include "facecore/error.hpp"
#include "facecore/fap_io.hpp"
#include "facecore/json_file.hpp"
#include "tracking/marker_tracker.hpp"

namespace rostro::eval {
namespace {

using nlohmann::json;

// A frame sink that tracks each frame as it is rendered: no clip is kept in memory or on disk
// (unless `frames` keeps it).
class TrackingSink : public render::FrameSink {
 public:
  TrackingSink(TrackedTake& take, const ScenarioFrameSink& frames) : take_(take), frames_(frames) {}
  void write(const cv::Mat& bgr) override {
    if (frames_) frames_(bgr);
    take_.add(bgr);
  }
  void finish() override {}
  long frames_written() const override { return static_cast<long>(take_.frames().size()); }

 private:
  TrackedTake& take_;
  const ScenarioFrameSink& frames_;
};

SuiteScenario parse_scenario(const json& j, const json& defaults, const std::string& where) {
  static const std::set<std::string> known = {
      "name",  "title", "fps",         "seconds",       "seed",         "fap",
      "yaw",   "pitch", "roll",        "motion_period", "distance_amp", "brightness",
      "light", "noise", "motion_blur", "occluder",      "neutral_lead", "size"};
  if (!j.is_object()) throw InputError(where + ": a scenario should be an object");
  for (const auto& [key, value] : j.items())
    if (!known.count(key)) throw InputError(where + ": unknown key '" + key + "'");
  auto num = [&](const char* key, double fallback) {
    if (j.contains(key)) {
      if (!j[key].is_number()) throw InputError(where + ": '" + key + "' should be a number");
      return j[key].get<double>();
    }
    return defaults.contains(key) ? defaults[key].get<double>() : fallback;
  };
  SuiteScenario s;
  s.name = j.value("name", "");
  if (s.name.empty()) throw InputError(where + ": a scenario needs a name");
  s.title = j.value("title", s.name);
  s.fps = num("fps", 25);
  s.seconds = num("seconds", 4);
  if (!(s.fps > 0) || !(s.seconds > 0))
    throw InputError(where + " (" + s.name + "): fps and seconds should be positive");
  if (j.contains("fap")) s.fap = data_file(j["fap"].get<std::string>());
  s.neutral_lead = num("neutral_lead", 0);
  if (!(s.neutral_lead >= 0))
    throw InputError(where + " (" + s.name + "): neutral_lead should not be negative");
  SynthOptions& o = s.synth;
  const json& size = j.contains("size") ? j["size"] : defaults.value("size", json());
  if (!size.is_null()) {
    if (!size.is_array() || size.size() != 2 || !size[0].is_number_integer() ||
        !size[1].is_number_integer() || size[0].get<int>() <= 0 || size[1].get<int>() <= 0)
      throw InputError(where + " (" + s.name + "): 'size' should be [width, height] in pixels");
    o.width = size[0].get<int>();
    o.height = size[1].get<int>();
  }
  o.seed = static_cast<unsigned>(num("seed", 1));
  o.yaw_deg = num("yaw", 0);
  o.pitch_deg = num("pitch", 0);
  o.roll_deg = num("roll", 0);
  o.motion_period_s = num("motion_period", o.motion_period_s);
  o.distance_amp = num("distance_amp", 0);
  o.brightness = num("brightness", 1);
  o.light_amp = num("light", 0);
  o.noise_sigma = num("noise", 0);
  o.motion_blur = num("motion_blur", 0);
  o.occluder = j.value("occluder", false);
  return s;
}

std::string percent(double share) {
  return fmt::format("{:.1f}%", 100.0 * share);
}

}  // namespace

std::filesystem::path default_suite_path() {
  return data_file("eval/suite.json");
}

SuiteDefinition load_suite(const std::filesystem::path& path) {
  const json j = read_json_file(path, "the suite file");
  SuiteDefinition d;
  d.scenarios = parse_scenario_list<SuiteScenario>(j, path, {"seconds", "seed", "fps", "size"},
                                                   parse_scenario);
  d.description = j.value("description", "");
  return d;
}

SuiteRow run_scenario(const SuiteScenario& s, const FaceModel& model,
                      const ExpressionLibrary* library, const tracking::MarkerLayout& layout,
                      const std::function<void(long, long)>& progress,
                      const tracking::TrackerOptions& tracker_options,
                      const ScenarioFrameSink& frames) {
  FapStream drive = s.fap.empty() ? range_of_motion(s.fps) : read_fap_stream(s.fap);
  if (s.fap.empty()) drive.header.fps = s.fps;
  const auto keep = static_cast<std::size_t>(std::lround(s.seconds * drive.header.fps));
  if (keep < drive.frames.size()) drive.frames.resize(keep);
  drive.header.frame_count = static_cast<long>(drive.frames.size());
  if (s.neutral_lead > 0) prepend_neutral(drive, s.neutral_lead);

  SynthOptions o = s.synth;
  o.dot_diameter_mm = layout.dot_diameter_mm;
  o.dark_dots = layout.polarity == tracking::DotPolarity::Dark;
  const auto markers = place_markers(model, layout);
  tracking::MarkerTracker tracker(layout, tracker_options);
  TrackedTake take(tracker, drive.header.fps);
  TrackingSink sink(take, frames);
  const long total = drive.header.frame_count;
  const SynthResult truth = synthesize(model, library, markers, drive, o, sink, [&](long done) {
    if (progress) progress(done, total);
  });
  SuiteRow row;
  row.name = s.name;
  row.title = s.title;
  row.frames = total;
  row.result = evaluate_tracks(truth.truth, take.frames());
  row.lost_by = take.lost_by();
  row.truth = truth.truth;
  row.tracks = take.take_frames();
  return row;
}

std::string suite_table_markdown(const std::vector<SuiteRow>& rows) {
  std::string out =
      "| scenario | frames | NME mean | AUC@0.08 | failure@0.08 | lost frames | lost / visible "
      "| swaps (events) |\n|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const SuiteRow& r : rows) {
    const TrackEvalResult& e = r.result;
    out += fmt::format("| {} | {} | {:.4f} | {:.3f} | {} | {} | {} / {} | {} ({}) |\n", r.title,
                       r.frames, e.nme.mean, e.auc, percent(e.failure_rate), e.lost_frames,
                       e.lost_observations, e.lost_observations + e.scored_observations,
                       e.swap_observations, e.swap_events);
  }
  return out;
}

std::string suite_table_text(const std::vector<SuiteRow>& rows) {
  std::string out =
      fmt::format("{:<12} {:>6} {:>9} {:>9} {:>9} {:>12} {:>14}\n", "scenario", "frames",
                  "NME mean", "AUC@0.08", "failure", "lost frames", "swaps (events)");
  for (const SuiteRow& r : rows) {
    const TrackEvalResult& e = r.result;
    out += fmt::format("{:<12} {:>6} {:>9.4f} {:>9.3f} {:>9} {:>12} {:>14}\n", r.name, r.frames,
                       e.nme.mean, e.auc, percent(e.failure_rate), e.lost_frames,
                       fmt::format("{} ({})", e.swap_observations, e.swap_events));
  }
  return out;
}

namespace {

// The reasons any row counts, in LostReason order.
std::vector<tracking::LostReason> reasons_counted(const std::vector<SuiteRow>& rows) {
  std::vector<tracking::LostReason> out;
  for (int k = 0; k < tracking::kLostReasonCount; ++k)
    for (const SuiteRow& r : rows)
      if (r.lost_by[static_cast<std::size_t>(k)] > 0) {
        out.push_back(static_cast<tracking::LostReason>(k));
        break;
      }
  return out;
}

long count(const SuiteRow& r, tracking::LostReason reason) {
  return r.lost_by[static_cast<std::size_t>(reason)];
}

}  // namespace

std::string loss_table_markdown(const std::vector<SuiteRow>& rows) {
  const auto reasons = reasons_counted(rows);
  std::string out = "| scenario |", rule = "|---|";
  for (const tracking::LostReason r : reasons)
    out += fmt::format(" {} |", tracking::to_string(r)), rule += "---:|";
  out += "\n" + rule + "\n";
  for (const SuiteRow& row : rows) {
    out += fmt::format("| {} |", row.title);
    for (const tracking::LostReason r : reasons) out += fmt::format(" {} |", count(row, r));
    out += "\n";
  }
  return out;
}

std::string loss_table_text(const std::vector<SuiteRow>& rows) {
  const auto reasons = reasons_counted(rows);
  std::string out = fmt::format("{:<12}", "scenario");
  for (const tracking::LostReason r : reasons)
    out +=
        fmt::format(" {:>{}}", tracking::to_string(r), std::string(tracking::to_string(r)).size());
  out += "\n";
  for (const SuiteRow& row : rows) {
    out += fmt::format("{:<12}", row.name);
    for (const tracking::LostReason r : reasons)
      out += fmt::format(" {:>{}}", count(row, r), std::string(tracking::to_string(r)).size());
    out += "\n";
  }
  return out;
}

void replace_markdown_section(const std::filesystem::path& path, const std::string& heading,
                              const std::string& body) {
  std::vector<std::string> lines;
  if (std::ifstream in(path); in)
    for (std::string line; std::getline(in, line);) lines.push_back(line);
  std::string out;
  bool replaced = false, skipping = false;
  for (const std::string& line : lines) {
    if (skipping && line.rfind("## ", 0) == 0) skipping = false;
    if (!replaced && line == heading) {
      out += heading + "\n\n" + body;
      if (!body.empty() && body.back() != '\n') out += "\n";
      out += "\n";
      replaced = skipping = true;
      continue;
    }
    if (!skipping) out += line + "\n";
  }
  if (!replaced) {
    if (!out.empty() && out.substr(out.size() >= 2 ? out.size() - 2 : 0) != "\n\n") out += "\n";
    out += heading + "\n\n" + body;
    if (!body.empty() && body.back() != '\n') out += "\n";
  }
  while (out.size() >= 2 && out.substr(out.size() - 2) == "\n\n") out.pop_back();
  AtomicFile file(path);
  file.write(out);
  file.commit();
}

}  // namespace rostro::eval
