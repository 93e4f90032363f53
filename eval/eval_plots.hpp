#pragma once
// The two charts `rostro eval` draws: the CED of one or more runs, and FAP curves over time.

#include <string>
#include <vector>

#include "eval/fap_metrics.hpp"
#include "eval/plot.hpp"
#include "facecore/fap_frame.hpp"

namespace rostro::eval {

struct CedRun {
  std::string label;
  std::vector<double> frame_nme;  // +infinity for failed frames
};

// CED curves from 0 to `x_max` with the threshold marked; each legend entry gives the AUC.
Chart ced_chart(const std::vector<CedRun>& runs, double threshold = kDefaultAucThreshold,
                double x_max = 0.1);

// One chart per FAP: the truth as a solid line, the estimate dashed, over time in seconds
// (frame number / fps of the truth). Frames where a stream does not set the FAP leave a gap.
std::vector<Chart> fap_curve_charts(const FapStream& truth, const FapStream& estimate,
                                    const std::vector<int>& faps);

// The `count` compared FAPs with the widest truth range, for a plot when none are named.
std::vector<int> widest_range_faps(const FapEvalResult& result, std::size_t count = 3);

}  // namespace rostro::eval
