#pragma once
// The standing accuracy suite (`rostro eval suite`): a fixed set of seeded synthetic clips
// (data/eval/suite.json), each rendered by synthesize(), tracked frame by frame as it is
// rendered (the tracker sees the rendered pixels, with no video compression in between) with
// automatic identification, and scored against the clip's exact truth by evaluate_tracks().
//
// suite.json:
//   { "description": ..., "seconds": 4, "seed": 1, "size": [640, 480],
//     "scenarios": [ { "name": "turns", "title": "head turns", "yaw": 25, "pitch": 15,
//                      "motion_period": 4 }, ... ] }
// Scenario keys (each optional): fps, seconds, seed, fap (a path relative to the data
// folder), yaw, pitch, roll, motion_period, distance_amp, brightness, light, noise,
// motion_blur, occluder (true/false), neutral_lead (seconds of neutral face before the drive,
// where the tracker can identify the markers), as the `rostro synth` options of the same names,
// and size ([width, height], as the top-level default).

#include <array>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "eval/synth.hpp"
#include "eval/track_metrics.hpp"
#include "tracking/marker_tracker.hpp"

namespace rostro::eval {

struct SuiteScenario {
  std::string name, title;
  std::filesystem::path fap;  // empty: the built-in range of motion
  double fps = 25, seconds = 4;
  double neutral_lead = 0;  // seconds of neutral face before the drive (not in `seconds`)
  SynthOptions synth;
};

struct SuiteDefinition {
  std::string description;
  std::vector<SuiteScenario> scenarios;
};

// Throws InputError naming the file and the scenario or key at fault.
SuiteDefinition load_suite(const std::filesystem::path& path);
// data/eval/suite.json
std::filesystem::path default_suite_path();

struct SuiteRow {
  std::string name, title;
  long frames = 0;
  TrackEvalResult result;
  // Marker-frames the tracker reported lost, by tracking::LostReason (None stays 0): every
  // layout marker, visible in the truth or not.
  std::array<long, tracking::kLostReasonCount> lost_by{};
  std::vector<tracking::TrackedFrame> truth, tracks;  // behind the figures, one per frame
};

// Each frame as rendered (8-bit BGR), before it is tracked: `rostro eval suite --out` writes
// them to a video.
using ScenarioFrameSink = std::function<void(const cv::Mat& bgr)>;

// Progress: (scenario index, frames done in it, frames in it).
using SuiteProgress = std::function<void(std::size_t, long, long)>;

// Runs one scenario with `layout` on `model`, tracked with `tracker_options`. Throws
// render::RenderUnavailable without OpenGL.
SuiteRow run_scenario(const SuiteScenario& scenario, const FaceModel& model,
                      const ExpressionLibrary* library, const tracking::MarkerLayout& layout,
                      const std::function<void(long, long)>& progress = {},
                      const tracking::TrackerOptions& tracker_options = {},
                      const ScenarioFrameSink& frames = {});

// The table: scenario, NME mean, AUC@0.08, failure rate, lost frames, swaps (events).
std::string suite_table_markdown(const std::vector<SuiteRow>& rows);
std::string suite_table_text(const std::vector<SuiteRow>& rows);
// The lost marker-frames by the rule that dropped them: a column per tracking::LostReason
// that any row counts.
std::string loss_table_markdown(const std::vector<SuiteRow>& rows);
std::string loss_table_text(const std::vector<SuiteRow>& rows);

// Replaces the section that starts with the line `heading` (up to the next "## " heading) in
// the Markdown file `path` by `heading` + `body`, or appends it when absent; the rest of the
// file is kept. Written atomically.
void replace_markdown_section(const std::filesystem::path& path, const std::string& heading,
                              const std::string& body);

}  // namespace rostro::eval
