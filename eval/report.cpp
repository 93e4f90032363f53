#include "eval/report.hpp"

#include <fmt/format.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "facecore/atomic_file.hpp"
#include "facecore/fap_table.hpp"

namespace rostro::eval {
namespace {

using json = nlohmann::ordered_json;

json number_or_null(double v) {
  return std::isfinite(v) ? json(v) : json(nullptr);
}

json optional_json(const std::optional<double>& v) {
  return v ? json(*v) : json(nullptr);
}

json stats_json(const ErrorStats& s) {
  return {
      {"count", s.count}, {"mean", s.mean}, {"median", s.median}, {"p95", s.p95}, {"max", s.max}};
}

std::string optional_text(const std::optional<double>& v, const char* format) {
  return v ? fmt::format(fmt::runtime(format), *v) : std::string("n/a");
}

}  // namespace

std::string track_report_json(const TrackEvalResult& r, const ReportSources& sources) {
  json markers = json::array();
  for (const MarkerResult& m : r.markers)
    markers.push_back({{"marker", m.marker},
                       {"fp", m.feature_point == FeaturePointId{} ? "" : m.feature_point.str()},
                       {"scored", m.scored},
                       {"lost", m.lost},
                       {"swap_frames", m.swap_frames},
                       {"swap_events", m.swap_events},
                       {"astray_frames", m.astray_frames},
                       {"error_px", stats_json(m.error_px)},
                       {"nme", stats_json(m.nme)}});
  json frames = json::array();
  for (const FrameResult& f : r.frames)
    frames.push_back({{"frame", f.frame},
                      {"nme", number_or_null(f.nme)},
                      {"norm_px", f.norm_distance},
                      {"norm_fallback", f.norm_fallback},
                      {"scored", f.scored},
                      {"lost", f.lost},
                      {"swaps", f.swaps},
                      {"astray", f.astray}});
  const json doc = {{"kind", "rostro.eval.tracks"},
                    {"version", 1},
                    {"truth", sources.truth},
                    {"estimate", sources.estimate},
                    {"options",
                     {{"norm", {r.options.norm_a, r.options.norm_b}},
                      {"match", r.options.match == MatchBy::Marker ? "marker" : "fp"},
                      {"threshold", r.options.threshold},
                      {"swap_threshold", r.options.swap_threshold},
                      {"lost_is_failure", r.options.lost_is_failure}}},
                    {"frames",
                     {{"truth", r.truth_frames},
                      {"estimate", r.estimate_frames},
                      {"scored", r.scored_frames},
                      {"missing", r.missing_frames},
                      {"extra", r.extra_frames},
                      {"norm_fallback", r.norm_fallback_frames}}},
                    {"norm_px_median", r.norm_distance_median},
                    {"nme", stats_json(r.nme)},
                    {"auc", r.auc},
                    {"failure_rate", r.failure_rate},
                    {"error_px", stats_json(r.error_px)},
                    {"observations", r.scored_observations},
                    {"lost", {{"observations", r.lost_observations}, {"frames", r.lost_frames}}},
                    {"swaps", {{"observations", r.swap_observations}, {"events", r.swap_events}}},
                    {"astray", r.astray_observations},
                    {"markers", markers},
                    {"per_frame", frames}};
  return doc.dump(2) + "\n";
}

std::string track_summary_markdown(const TrackEvalResult& r, const ReportSources& sources) {
  const double a = r.options.threshold;
  std::string md = "# Tracking accuracy\n\n";
  md += fmt::format("Truth `{}`, estimate `{}`.\n\n", sources.truth, sources.estimate);
  md += fmt::format(
      "{} frames scored ({} with no estimate frame); NME normalised by the distance {}-{} "
      "(median {:.1f} px).\n\n",
      r.scored_frames, r.missing_frames, r.options.norm_a, r.options.norm_b,
      r.norm_distance_median);
  md += "| NME mean | NME median | NME p95 | AUC@" + fmt::format("{:.2f}", a) + " | failure@" +
        fmt::format("{:.2f}", a) +
        " | error px mean | error px p95 | lost obs. (frames) | swaps (events) | astray |\n";
  md += "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  md += fmt::format(
      "| {:.4f} | {:.4f} | {:.4f} | {:.3f} | {:.1f}% | {:.2f} | {:.2f} | {} ({}) | {} ({}) | {} "
      "|\n\n",
      r.nme.mean, r.nme.median, r.nme.p95, r.auc, 100 * r.failure_rate, r.error_px.mean,
      r.error_px.p95, r.lost_observations, r.lost_frames, r.swap_observations, r.swap_events,
      r.astray_observations);
  md += "## Per marker (pixels)\n\n";
  md += "| marker | fp | scored | mean | median | p95 | max | lost | swap events |\n";
  md += "|---|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const MarkerResult& m : r.markers)
    md += fmt::format("| {} | {} | {} | {:.2f} | {:.2f} | {:.2f} | {:.2f} | {} | {} |\n", m.marker,
                      m.feature_point == FeaturePointId{} ? "" : m.feature_point.str(), m.scored,
                      m.error_px.mean, m.error_px.median, m.error_px.p95, m.error_px.max, m.lost,
                      m.swap_events);
  return md;
}

std::string fap_report_json(const FapEvalResult& r, const ReportSources& sources) {
  json faps = json::array();
  for (const FapError& f : r.faps)
    faps.push_back({{"fap", f.fap},
                    {"name", std::string(fap_info(f.fap).name)},
                    {"unit", std::string(unit_name(fap_info(f.fap).unit))},
                    {"frames", f.frames},
                    {"rms", f.rms},
                    {"rms_share_of_range", optional_json(f.rms_share_of_range)},
                    {"correlation", optional_json(f.correlation)},
                    {"mean_error", f.mean_error},
                    {"max_abs_error", f.max_abs_error},
                    {"truth_min", f.truth_min},
                    {"truth_max", f.truth_max}});
  const json doc = {
      {"kind", "rostro.eval.faps"},
      {"version", 1},
      {"truth", sources.truth},
      {"estimate", sources.estimate},
      {"frames",
       {{"truth", r.truth_frames}, {"estimate", r.estimate_frames}, {"matched", r.matched_frames}}},
      {"mean_rms", r.mean_rms},
      {"mean_share_of_range", optional_json(r.mean_share_of_range)},
      {"mean_correlation", optional_json(r.mean_correlation)},
      {"faps", faps}};
  return doc.dump(2) + "\n";
}

std::string fap_summary_markdown(const FapEvalResult& r, const ReportSources& sources) {
  std::string md = "# FAP accuracy\n\n";
  md += fmt::format("Truth `{}`, estimate `{}`: {} matched frames, {} FAPs compared.\n\n",
                    sources.truth, sources.estimate, r.matched_frames, r.faps.size());
  md += fmt::format("Mean RMS {:.2f}; mean RMS / truth range {}; mean correlation {}.\n\n",
                    r.mean_rms, optional_text(r.mean_share_of_range, "{:.3f}"),
                    optional_text(r.mean_correlation, "{:.3f}"));
  md += "| FAP | name | unit | frames | RMS | RMS / range | correlation | bias |\n";
  md += "|---:|---|---|---:|---:|---:|---:|---:|\n";
  for (const FapError& f : r.faps)
    md += fmt::format("| {} | {} | {} | {} | {:.2f} | {} | {} | {:.2f} |\n", f.fap,
                      fap_info(f.fap).name, unit_name(fap_info(f.fap).unit), f.frames, f.rms,
                      optional_text(f.rms_share_of_range, "{:.3f}"),
                      optional_text(f.correlation, "{:.3f}"), f.mean_error);
  return md;
}

void write_text_file(const std::filesystem::path& path, const std::string& text) {
  AtomicFile file(path);
  file.write(text);
  file.commit();
}

std::string photo_report_json(const std::vector<PhotoRow>& rows, const std::string& scenes,
                              const std::vector<std::string>& tracker_options) {
  json out = json::array();
  for (const PhotoRow& r : rows) {
    const TrackEvalResult& e = r.suite.result;
    const bool scored = e.scored_observations > 0;
    out.push_back(
        {{"name", r.suite.name},
         {"title", r.suite.title},
         {"frames", r.suite.frames},
         {"median_px", scored ? number_or_null(e.error_px.median) : json(nullptr)},
         {"p95_px", scored ? number_or_null(e.error_px.p95) : json(nullptr)},
         {"swapped", e.swap_observations},
         {"swap_events", e.swap_events},
         {"astray", e.astray_observations},
         {"lost", e.lost_observations},
         {"visible", e.lost_observations + e.scored_observations},
         {"hidden_reported", r.hidden_reported},
         {"occlusions", r.occlusions},
         {"worst_reacquire", r.worst_reacquire < 0 ? json(nullptr) : json(r.worst_reacquire)}});
  }
  const json doc = {{"kind", "rostro.eval.photos"},
                    {"scenes", scenes},
                    {"options", tracker_options},
                    {"rows", out}};
  return doc.dump(2) + "\n";
}

}  // namespace rostro::eval
