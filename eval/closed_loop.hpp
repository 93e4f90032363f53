#pragma once
// The closed loop of issue 6 (`rostro eval loop`): a known FAP stream drives the default head
// (eval::synthesize, in-process, no video file), the rendered frames are tracked with
// automatic identification, mapped back to FAPs by mapping::TakeMapper (the actor calibrated
// from the clip's first second, which a neutral lead-in keeps neutral; the clip's own camera
// intrinsics), and the result is scored against the driving stream with evaluate_faps().
// Three mappings per clip: the Ceres fit and the seed's 2D baseline on the tracked markers,
// and the Ceres fit on the exact truth tracks (no tracking error: what is left is the fit's).
//
// "Tracked FAPs" are the FAPs the Ceres fit measures directly with the clip's calibrated
// profile (the marker model's FAPs, plus head pitch/yaw/roll 48-50 from its pose), not those
// the hierarchy derives, and of those only the ones whose truth has a non-zero range. The aim
// is on every one of them: RMS error within `aim` of the FAP's range in the truth.
//
// closed_loop.json:
//   { "description": ..., "size": [640, 480], "seed": 1, "neutral_lead": 1,
//     "calibration_seconds": 1, "scenarios": [
//       { "name": "turns", "title": "...", "drive": "range_of_motion",
//         "head_yaw": 25, "head_pitch": 15 }, ... ] }
// Scenario keys: name, title, drive ("range_of_motion"; a .fap path under the data folder; or
// "shared:REL" under the shared folder: $ROSTRO_SHARED, else ../shared beside the repository),
// fps (range of motion only), seconds (cut the drive), seed, neutral_lead, head_yaw,
// head_pitch, head_roll, head_period (eval::HeadSweeps, starting after the lead-in), aim (a
// share: default 0.05 with a still head, 0.08 with head sweeps), markerless_aim (the aim when
// the head is rendered bare and tracked by its landmarks: default 0.10 still, 0.15 with head
// sweeps, issue 17's), head_vertices (render the head `rostro head --vertices N` generates
// instead of the one given: the same head sampled elsewhere, a face no rule was tuned on; 0,
// the default: the one given), camera_elevation (degrees the camera is held above the face's
// level, below if negative: a face seen from another height), size ([width, height]). Top-level
// keys size, seed, fps, neutral_lead, calibration_seconds, head_period, head_vertices are
// defaults.

#include <array>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "eval/fap_metrics.hpp"
#include "eval/head_sweeps.hpp"
#include "eval/synth.hpp"
#include "mapping/fap_solver.hpp"
#include "tracking/face_tracker.hpp"
#include "tracking/layout.hpp"
#include "tracking/marker_tracker.hpp"

namespace rostro::eval {

struct LoopScenario {
  std::string name, title;
  std::string drive = "range_of_motion";  // as written in the file
  std::filesystem::path fap;              // resolved; empty: the built-in range of motion
  std::string skip_reason;                // non-empty: the drive file is absent, skip it
  double fps = 25;                        // of the range of motion
  double seconds = 0;                     // > 0: the drive cut to this length
  double neutral_lead = 1.0;              // seconds of neutral face before the drive
  double calibration_seconds = 1.0;       // the first frames the actor is calibrated from
  HeadSweeps head;                        // start_s is set to the lead-in
  double aim = 0.05;                      // RMS / range, every tracked FAP
  double markerless_aim = 0.10;           // the same for the bare head (`--markerless`)
  int head_vertices = 0;                  // > 0: the generated head of about this many
  // > 0: a fourth mapping, the Ceres fit on the exact tracks with Gaussian noise of this
  // sigma (pixels, each coordinate, seeded by synth.seed) added: how precise a tracker's points
  // must be for the aim.
  double truth_noise_px = 0;
  SynthOptions synth;
};

struct LoopDefinition {
  std::string description;
  std::vector<LoopScenario> scenarios;
};

// Throws InputError naming the file, the scenario and the key at fault. A "shared:" drive
// that is absent is not an error: the scenario carries a skip_reason.
LoopDefinition load_closed_loop(const std::filesystem::path& path);
// data/eval/closed_loop.json
std::filesystem::path default_closed_loop_path();
// $ROSTRO_SHARED, else the shared folder beside the repository (data_dir()/../../shared).
std::filesystem::path shared_dir();

// The driving stream of a scenario: drive, cut, neutral lead-in, head sweeps.
FapStream loop_drive(const LoopScenario& scenario);

// CeresOnNoisyTruth runs only when the scenario sets truth_noise_px.
enum class LoopMethod { Ceres, Seed2d, CeresOnTruth, CeresOnNoisyTruth };
inline constexpr std::array<LoopMethod, 3> kLoopMethods = {LoopMethod::Ceres, LoopMethod::Seed2d,
                                                           LoopMethod::CeresOnTruth};
std::string method_label(LoopMethod m);

// One method's score over the tracked FAPs.
struct LoopScore {
  LoopMethod method = LoopMethod::Ceres;
  double noise_px = 0;  // CeresOnNoisyTruth: the noise's sigma
  FapStream estimate;   // what the mapping wrote, frame by frame
  FapEvalResult eval;   // every FAP both streams set
  long calibration_frames = 0;
  long fitted_frames = 0;  // output frames with any FAP set
  // Over the tracked FAPs this method outputs:
  int scored = 0;
  std::vector<int> not_output;  // tracked FAPs this method never writes (seed2d: the head)
  double mean_share = 0, max_share = 0;
  // The least share of its truth frames a scored tracked FAP is compared over: below 1 when
  // the method writes nothing for it in some frames (its marker lost), which the RMS omits.
  double coverage = 1.0;
  int worst_fap = 0;
  bool met = false;  // every tracked FAP scored and within the aim
  // Why this method wrote nothing (its actor calibration failed on these tracks, say); empty
  // when it ran. One method's failure does not end the scenario: the others are still scored.
  std::string failure;
  const FapError* find(int fap) const;
  std::string label() const;  // method_label(), with the noise's sigma where there is one
};

struct LoopResult {
  std::string name, title;
  long frames = 0;
  double aim = 0;
  std::vector<int> tracked;  // the tracked FAPs (see above), ascending
  // FAPs the drive moves that are not tracked: derived by the hierarchy (inner lip from outer
  // lip, ...) or on no marker. Listed so that what the aim does not cover is visible.
  std::vector<int> driven_untracked;
  FapStream drive;  // the truth: the driving stream as rendered
  // The marker tracks the tracker followed on the rendered frames, and the exact ones the
  // renderer projected (for `rostro eval tracks`).
  std::vector<tracking::TrackedFrame> tracks, truth_tracks;
  std::vector<LoopScore> scores;  // in kLoopMethods order, then CeresOnNoisyTruth if run
  const LoopScore& score(LoopMethod m) const;
};

// Progress of the rendering and tracking: (frames done, frames in the clip).
using LoopProgress = std::function<void(long, long)>;

// Makes the tracker a scenario's frames go through. Its layout() is what the clip shows (dots
// and tags are painted; landmarks are not: the head is rendered bare) and what the actor is
// calibrated on.
using TrackerFactory = std::function<std::unique_ptr<tracking::FaceTracker>()>;

// Runs one scenario (not a skipped one): `model` rendered, tracked by make_tracker()'s tracker
// and fitted (both Ceres methods) with `solver_options`, the actor calibrated on `model`'s own
// prior (its feature points and deformation), as `rostro capture` calibrates on the default
// head. Throws render::RenderUnavailable without OpenGL.
LoopResult run_loop_scenario(const LoopScenario& scenario, const FaceModel& model,
                             const ExpressionLibrary* library, const TrackerFactory& make_tracker,
                             const LoopProgress& progress = {},
                             const mapping::SolverOptions& solver_options = {});
// The same with a MarkerTracker on `layout` with `tracker_options`.
LoopResult run_loop_scenario(const LoopScenario& scenario, const FaceModel& model,
                             const ExpressionLibrary* library, const tracking::MarkerLayout& layout,
                             const LoopProgress& progress = {},
                             const tracking::TrackerOptions& tracker_options = {},
                             const mapping::SolverOptions& solver_options = {});

// The summary (scenario x method: mean and max share over the tracked FAPs, worst FAP, aim,
// met) and one per-FAP table per scenario (RMS in the FAP's unit and as a share of range).
std::string loop_summary_text(const std::vector<LoopResult>& results);
std::string loop_summary_markdown(const std::vector<LoopResult>& results);
std::string loop_fap_table_text(const LoopResult& result);
std::string loop_fap_table_markdown(const LoopResult& result);
// "Driven, not tracked: ..." with the Ceres RMS share of each; empty when there is none.
std::string loop_untracked_line(const LoopResult& result);
// One paragraph: what "tracked FAPs" means and how the figures are made.
std::string loop_definitions(bool markerless = false);

}  // namespace rostro::eval
