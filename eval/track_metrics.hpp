#pragma once
// Scores estimated marker tracks against ground truth: per-marker pixel errors, the per-frame
// normalised mean error (NME) with its CED, AUC and failure rate (300-VW protocol, see
// error_stats.hpp), lost observations and identity swaps.
//
// Definitions (docs/evaluation.md repeats them for users):
// - Frames are matched by frame number. A truth frame is scored when at least one marker is
//   visible (valid) in it; estimate frames with no truth frame are only counted (extra).
// - A marker is matched by its marker id (or, with MatchBy::FeaturePoint, by its feature
//   point). It is *scored* in a frame when it is visible in the truth and valid in the
//   estimate, and *lost* when it is visible in the truth but invalid or missing in the
//   estimate (a missing estimate frame loses every visible marker).
// - The normalising distance d of a frame is the truth distance between the two named
//   points (default the outer eye corners 3.7 and 3.12). In a frame where either is not
//   visible, d is the median d of the frames where both are.
// - NME of a frame = mean over its scored markers of |estimate - truth| / d. A scored frame
//   with no scored marker (everything lost) has NME = +infinity: a failure, off the CED.
// - Identity swap: a scored marker whose estimate lies nearer another visible marker's truth
//   than its own truth, while its own error exceeds swap_threshold * d. The threshold keeps
//   markers that nearly touch (inner and outer lip at rest) from counting as swapped when
//   the estimate is good anyway. A run of consecutive swapped frames of one marker is one
//   swap event.
// - Astray: a scored marker as far from its own truth as a swap (beyond swap_threshold * d)
//   but nearer its own truth than any other marker's: named on something that is no marker
//   (a lip corner, a nostril) or followed off its dot. As wrong as a swap, and as silent.

#include <span>
#include <string>
#include <vector>

#include "eval/error_stats.hpp"
#include "tracking/tracked_frame.hpp"

namespace rostro::eval {

enum class MatchBy { Marker, FeaturePoint };

struct TrackEvalOptions {
  // Each a feature point ("3.7") or a marker id of the truth.
  std::string norm_a = "3.7";
  std::string norm_b = "3.12";
  MatchBy match = MatchBy::Marker;
  double threshold = kDefaultAucThreshold;  // AUC and failure threshold on NME
  double swap_threshold = 0.05;             // own error beyond this * d before a swap counts
  // When true a frame with any lost marker counts as a failure (NME = +infinity).
  bool lost_is_failure = false;
};

struct MarkerResult {
  std::string marker;
  FeaturePointId feature_point;
  ErrorStats error_px;  // over the frames where it is scored
  ErrorStats nme;       // the same errors divided by each frame's d
  long scored = 0;
  long lost = 0;
  long swap_frames = 0;
  long swap_events = 0;
  long astray_frames = 0;
};

struct FrameResult {
  long frame = 0;
  double norm_distance = 0;    // d in pixels
  bool norm_fallback = false;  // d is the median, the pair was not visible
  double nme = 0;              // +infinity when nothing could be scored
  int scored = 0;
  int lost = 0;
  int swaps = 0;
  int astray = 0;
};

struct TrackEvalResult {
  TrackEvalOptions options;
  long truth_frames = 0;
  long estimate_frames = 0;
  long scored_frames = 0;   // truth frames with a visible marker
  long missing_frames = 0;  // scored truth frames with no estimate frame at all
  long extra_frames = 0;    // estimate frames with no truth frame
  long norm_fallback_frames = 0;
  double norm_distance_median = 0;

  std::vector<FrameResult> frames;  // one per scored truth frame, in truth order
  std::vector<double> frame_nme;    // the NME column of `frames`
  ErrorStats nme;                   // over finite frame NMEs
  ErrorStats error_px;              // over every scored observation
  double auc = 0;
  double failure_rate = 0;

  long scored_observations = 0;
  long lost_observations = 0;
  long lost_frames = 0;  // frames with at least one lost marker
  long swap_observations = 0;
  long swap_events = 0;
  long astray_observations = 0;
  std::vector<MarkerResult> markers;  // in order of first appearance in the truth
};

// Throws InputError when the normalising pair is never visible in the truth, when a frame
// number repeats, or when a marker repeats within a frame (or a feature point, matching by
// feature point).
TrackEvalResult evaluate_tracks(std::span<const tracking::TrackedFrame> truth,
                                std::span<const tracking::TrackedFrame> estimate,
                                const TrackEvalOptions& options = {});

}  // namespace rostro::eval
