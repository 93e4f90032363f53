#pragma once
// Scores an estimated FAP stream against a truth stream, FAP by FAP.
//
// Frames are matched by frame number. A low-level FAP (3..68) is compared over the matched
// frames where both streams set it; FAPs 1 and 2 (viseme, expression) are structured and left
// out. Per FAP: RMS error in the FAP's own unit (FAPU, or AU for rotations), that RMS as a
// share of the truth's range (max - min over the compared frames), the mean error (bias),
// the largest absolute error and the Pearson correlation. The share and the correlation are
// undefined (nullopt) when the truth (or, for the correlation, either stream) is constant.

#include <optional>
#include <vector>

#include "facecore/fap_frame.hpp"

namespace rostro::eval {

struct FapError {
  int fap = 0;
  long frames = 0;  // matched frames where both streams set it
  double rms = 0;
  double mean_error = 0;  // estimate - truth
  double max_abs_error = 0;
  double truth_min = 0;
  double truth_max = 0;
  std::optional<double> rms_share_of_range;
  std::optional<double> correlation;
};

struct FapEvalResult {
  long truth_frames = 0;
  long estimate_frames = 0;
  long matched_frames = 0;
  std::vector<FapError> faps;                 // by FAP id, only FAPs compared in at least one frame
  double mean_rms = 0;                        // mean of the per-FAP RMS values
  std::optional<double> mean_share_of_range;  // over the FAPs where it is defined
  std::optional<double> mean_correlation;
};

// Throws InputError when a frame number repeats in either stream or no frame matches.
FapEvalResult evaluate_faps(const FapStream& truth, const FapStream& estimate);

// Pearson correlation; nullopt when the sizes differ, fewer than 2 values, or either is constant.
std::optional<double> pearson(const std::vector<double>& a, const std::vector<double>& b);

}  // namespace rostro::eval
