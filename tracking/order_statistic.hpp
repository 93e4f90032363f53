#pragma once
// The robust middle values the tracker judges by: the median motion of a face's markers, their
// typical spacing, contrast and size. An element of the sample itself (no interpolation), found
// in linear time; eval/error_stats.hpp interpolates instead, for reported figures.

#include <algorithm>
#include <span>
#include <utility>
#include <vector>

namespace rostro::tracking {

// The element of rank floor(share * n) of `values` (0 <= share < 1; 0.5: the median, the upper
// of the two middle ones for an even count); `fallback` when `values` is empty.
inline double order_statistic(std::vector<double> values, double share, double fallback = 0) {
  if (values.empty()) return fallback;
  const auto rank = std::min(static_cast<long>(share * static_cast<double>(values.size())),
                             static_cast<long>(values.size()) - 1);
  std::nth_element(values.begin(), values.begin() + rank, values.end());
  return values[static_cast<size_t>(rank)];
}

// order_statistic(values, 0.5, 0).
inline double median(std::vector<double> values) {
  return order_statistic(std::move(values), 0.5, 0);
}

// median(values) without a copy: `values` is reordered. For the small samples the tracker
// judges every marker by on every frame.
inline double median_in_place(std::span<double> values) {
  if (values.empty()) return 0;
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

}  // namespace rostro::tracking
