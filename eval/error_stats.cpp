#include "eval/error_stats.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace rostro::eval {

double quantile(std::vector<double> values, double q) {
  std::sort(values.begin(), values.end());
  const double position = q * static_cast<double>(values.size() - 1);
  const auto below = static_cast<std::size_t>(std::floor(position));
  const std::size_t above = std::min(below + 1, values.size() - 1);
  const double t = position - static_cast<double>(below);
  return values[below] + t * (values[above] - values[below]);
}

ErrorStats summarize(std::span<const double> values) {
  std::vector<double> finite;
  finite.reserve(values.size());
  for (double v : values)
    if (std::isfinite(v)) finite.push_back(v);
  ErrorStats s;
  s.count = finite.size();
  if (finite.empty()) return s;
  s.mean = std::accumulate(finite.begin(), finite.end(), 0.0) / static_cast<double>(s.count);
  s.median = quantile(finite, 0.5);
  s.p95 = quantile(finite, 0.95);
  s.max = *std::max_element(finite.begin(), finite.end());
  return s;
}

double ced_at(std::span<const double> errors, double e) {
  if (errors.empty()) return 0;
  const auto below = std::count_if(errors.begin(), errors.end(), [e](double v) { return v <= e; });
  return static_cast<double>(below) / static_cast<double>(errors.size());
}

double auc_at(std::span<const double> errors, double threshold) {
  if (errors.empty() || threshold <= 0) return 0;
  double sum = 0;
  for (double e : errors)
    if (e < threshold) sum += 1.0 - std::max(e, 0.0) / threshold;
  return sum / static_cast<double>(errors.size());
}

double failure_rate(std::span<const double> errors, double threshold) {
  if (errors.empty()) return 0;
  const auto failed =
      std::count_if(errors.begin(), errors.end(), [threshold](double v) { return v > threshold; });
  return static_cast<double>(failed) / static_cast<double>(errors.size());
}

std::vector<CurvePoint> ced_curve(std::span<const double> errors, double max_error) {
  std::vector<double> sorted(errors.begin(), errors.end());
  std::sort(sorted.begin(), sorted.end());
  const double n = static_cast<double>(std::max<std::size_t>(sorted.size(), 1));
  std::vector<CurvePoint> curve;
  double share = 0;
  curve.push_back({0.0, ced_at(errors, 0.0)});
  share = curve.back().y;
  for (std::size_t i = 0; i < sorted.size(); ++i) {
    const double e = sorted[i];
    if (e <= 0) continue;
    if (e > max_error) break;
    // A vertical step at e: the curve holds its level up to e, then jumps.
    std::size_t j = i;
    while (j + 1 < sorted.size() && sorted[j + 1] == e) ++j;
    curve.push_back({e, share});
    share = static_cast<double>(j + 1) / n;
    curve.push_back({e, share});
    i = j;
  }
  curve.push_back({max_error, share});
  return curve;
}

}  // namespace rostro::eval
