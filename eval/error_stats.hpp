#pragma once
// Summary statistics of an error sample and the 300-VW style cumulative error distribution.
//
// The 300-VW protocol (Shen et al., ICCV 2015 workshops; the same as 300-W) scores a tracker
// per frame by the normalised mean error (NME), draws the cumulative error distribution
// (CED: the share of frames whose NME is at most e, over e), and reports
//   AUC@a     = (1/a) * integral_0^a CED(e) de   (area under the CED up to a, normalised)
//   failure@a = share of frames with NME > a
// with a = 0.08. Frames that could not be scored at all carry NME = +infinity: they never
// enter the CED and always count as failures.

#include <cstddef>
#include <span>
#include <vector>

namespace rostro::eval {

inline constexpr double kDefaultAucThreshold = 0.08;

struct ErrorStats {
  std::size_t count = 0;
  double mean = 0;
  double median = 0;
  double p95 = 0;
  double max = 0;
};

// Statistics of finite values; all zero when `values` is empty.
ErrorStats summarize(std::span<const double> values);

// The q-quantile (0..1) of `values` with linear interpolation between order statistics (the
// numpy default, Hyndman-Fan type 7). `values` must not be empty.
double quantile(std::vector<double> values, double q);

// CED(e): the share of `errors` at most `e` (an empty sample gives 0).
double ced_at(std::span<const double> errors, double e);

// The exact AUC of the step CED: each error e_i < a contributes (1 - e_i / a) / N. Equal to
// the integral above, with no sampling of the curve.
double auc_at(std::span<const double> errors, double threshold = kDefaultAucThreshold);

// The share of errors strictly above `threshold` (+infinity included).
double failure_rate(std::span<const double> errors, double threshold = kDefaultAucThreshold);

// Points (e, CED(e)) of the step curve from 0 to `max_error`, for plotting: one point at
// each distinct error inside the range plus both ends.
struct CurvePoint {
  double x = 0;
  double y = 0;
};
std::vector<CurvePoint> ced_curve(std::span<const double> errors, double max_error);

}  // namespace rostro::eval
