#pragma once
// Reports of an evaluation: a JSON document with every figure (for scripts and the suite)
// and a short Markdown summary for people.

#include <filesystem>
#include <string>

#include "eval/fap_metrics.hpp"
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

// Writes text through AtomicFile. Throws InputError on failure.
void write_text_file(const std::filesystem::path& path, const std::string& text);

}  // namespace rostro::eval
