#include "eval/eval_plots.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "facecore/fap_table.hpp"

namespace rostro::eval {

Chart ced_chart(const std::vector<CedRun>& runs, double threshold, double x_max) {
  Chart c;
  c.title = "Cumulative error distribution";
  c.x_label = "NME (error / inter-ocular distance)";
  c.y_label = "Share of frames";
  c.x_min = 0;
  c.x_max = x_max;
  c.y_min = 0;
  c.y_max = 1;
  c.legend = LegendPlace::BottomRight;
  char text[64];
  std::snprintf(text, sizeof text, "%.2f", threshold);
  c.markers.push_back({threshold, std::string("threshold ") + text});
  for (const CedRun& run : runs) {
    Series s;
    std::snprintf(text, sizeof text, " (AUC@%.2f %.3f)", threshold,
                  auc_at(run.frame_nme, threshold));
    s.label = run.label + text;
    s.points = ced_curve(run.frame_nme, x_max);
    c.series.push_back(std::move(s));
  }
  return c;
}

std::vector<Chart> fap_curve_charts(const FapStream& truth, const FapStream& estimate,
                                    const std::vector<int>& faps) {
  const double fps = truth.header.fps > 0 ? truth.header.fps : 25.0;
  constexpr double kGap = std::numeric_limits<double>::quiet_NaN();
  std::vector<Chart> charts;
  for (int id : faps) {
    const FapInfo& info = fap_info(id);
    Chart c;
    c.title = "FAP " + std::to_string(id) + " " + std::string(info.name);
    c.x_label = "time (s)";
    c.y_label = std::string(unit_name(info.unit)) + " units";
    c.legend = LegendPlace::Above;
    auto curve = [&](const FapStream& s, const char* label, bool dashed) {
      Series series;
      series.label = label;
      series.dashed = dashed;
      for (const FapFrame& f : s.frames)
        series.points.push_back({static_cast<double>(f.index) / fps, f.has(id) ? f.get(id) : kGap});
      return series;
    };
    c.series.push_back(curve(truth, "truth", false));
    c.series.push_back(curve(estimate, "estimate", true));
    charts.push_back(std::move(c));
  }
  return charts;
}

std::vector<int> widest_range_faps(const FapEvalResult& result, std::size_t count) {
  std::vector<FapError> sorted = result.faps;
  std::stable_sort(sorted.begin(), sorted.end(), [](const FapError& a, const FapError& b) {
    return a.truth_max - a.truth_min > b.truth_max - b.truth_min;
  });
  std::vector<int> ids;
  for (std::size_t i = 0; i < sorted.size() && i < count; ++i) ids.push_back(sorted[i].fap);
  std::sort(ids.begin(), ids.end());
  return ids;
}

}  // namespace rostro::eval
