#include "eval/fap_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "facecore/error.hpp"

namespace rostro::eval {
namespace {

std::map<long, const FapFrame*> by_index(const FapStream& s, const char* side) {
  std::map<long, const FapFrame*> index;
  for (const FapFrame& f : s.frames)
    if (!index.emplace(f.index, &f).second)
      throw InputError(std::string(side) + " (" + s.header.name + "): frame " +
                       std::to_string(f.index) + " appears twice");
  return index;
}

}  // namespace

std::optional<double> pearson(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size() || a.size() < 2) return std::nullopt;
  const double n = static_cast<double>(a.size());
  double ma = 0, mb = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    ma += a[i];
    mb += b[i];
  }
  ma /= n;
  mb /= n;
  double sab = 0, saa = 0, sbb = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  if (saa <= 0 || sbb <= 0) return std::nullopt;
  return sab / std::sqrt(saa * sbb);
}

FapEvalResult evaluate_faps(const FapStream& truth, const FapStream& estimate) {
  FapEvalResult r;
  r.truth_frames = static_cast<long>(truth.frames.size());
  r.estimate_frames = static_cast<long>(estimate.frames.size());
  const auto truth_index = by_index(truth, "truth");
  const auto est_index = by_index(estimate, "estimate");

  std::vector<std::pair<const FapFrame*, const FapFrame*>> matched;
  for (const auto& [frame, t] : truth_index) {
    const auto it = est_index.find(frame);
    if (it != est_index.end()) matched.emplace_back(t, it->second);
  }
  r.matched_frames = static_cast<long>(matched.size());
  if (matched.empty())
    throw InputError("no frame number of the estimate (" + estimate.header.name +
                     ") occurs in the truth (" + truth.header.name + ")");

  double share_sum = 0, corr_sum = 0;
  int share_count = 0, corr_count = 0;
  for (int id = 3; id <= kFapCount; ++id) {
    std::vector<double> t_values, e_values;
    for (const auto& [t, e] : matched) {
      if (!t->has(id) || !e->has(id)) continue;
      t_values.push_back(t->get(id));
      e_values.push_back(e->get(id));
    }
    if (t_values.empty()) continue;
    FapError fe;
    fe.fap = id;
    fe.frames = static_cast<long>(t_values.size());
    double sq = 0, sum = 0;
    for (std::size_t i = 0; i < t_values.size(); ++i) {
      const double d = e_values[i] - t_values[i];
      sq += d * d;
      sum += d;
      fe.max_abs_error = std::max(fe.max_abs_error, std::abs(d));
    }
    const double n = static_cast<double>(t_values.size());
    fe.rms = std::sqrt(sq / n);
    fe.mean_error = sum / n;
    const auto [lo, hi] = std::minmax_element(t_values.begin(), t_values.end());
    fe.truth_min = *lo;
    fe.truth_max = *hi;
    if (*hi > *lo) fe.rms_share_of_range = fe.rms / (*hi - *lo);
    fe.correlation = pearson(t_values, e_values);
    if (fe.rms_share_of_range) {
      share_sum += *fe.rms_share_of_range;
      ++share_count;
    }
    if (fe.correlation) {
      corr_sum += *fe.correlation;
      ++corr_count;
    }
    r.mean_rms += fe.rms;
    r.faps.push_back(fe);
  }
  if (!r.faps.empty()) r.mean_rms /= static_cast<double>(r.faps.size());
  if (share_count > 0) r.mean_share_of_range = share_sum / share_count;
  if (corr_count > 0) r.mean_correlation = corr_sum / corr_count;
  return r;
}

}  // namespace rostro::eval
