#pragma once
// Reports of an evaluation: a JSON document with every figure (for scripts and the suite)
// and a short Markdown summary for people.

#include <filesystem>
#include <string>

#include "eval/fap_metrics.hpp"
#include "eval/photo_suite.hpp"
#include "eval/track_metrics.hpp"

namespace rostro::eval {

struct ReportSources {
  std::string truth;     // the truth file or folder as given
  std::string estimate;  // the estimate file
};

// JSON: "kind", "truth", "estimate", "options", "frames" counts, "nme" stats, "auc",
// "failure_rate", "error_px", "lost", "swaps", "markers" (per marker) and "per_frame".
// Infinite per-frame NME (nothing scored) is written as null.
std::string track_report_json(const TrackEvalResult& result, const ReportSources& sources);
std::string track_summary_markdown(const TrackEvalResult& result, const ReportSources& sources);

std::string fap_report_json(const FapEvalResult& result, const ReportSources& sources);
std::string fap_summary_markdown(const FapEvalResult& result, const ReportSources& sources);

// `rostro eval photos`' rows (eval/photo_suite.hpp) as JSON for scripts (--report): "kind"
// ("rostro.eval.photos"), "scenes" (the file as given), "options" (the tracker options as
// given, NAME=VALUE) and "rows", each with name, title, frames, median_px and p95_px (null
// when nothing was scored), swapped, swap_events, astray, lost, visible, hidden_reported,
// occlusions and worst_reacquire (frames; null when one never came back; 0 without an
// occlusion).
std::string photo_report_json(const std::vector<PhotoRow>& rows, const std::string& scenes,
                              const std::vector<std::string>& tracker_options);

// Writes text through AtomicFile. Throws InputError on failure.
void write_text_file(const std::filesystem::path& path, const std::string& text);

}  // namespace rostro::eval
