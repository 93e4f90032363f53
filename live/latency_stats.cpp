#include "live/latency_stats.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace rostro::live {

void LatencyStats::add(double ms) {
  if (samples_.size() < window_) {
    samples_.push_back(ms);
  } else {
    samples_[next_] = ms;
    next_ = (next_ + 1) % window_;
  }
  ++total_;
}

double LatencyStats::quantile(double q) const {
  if (samples_.empty()) return 0.0;
  std::vector<double> sorted = samples_;
  const auto rank = static_cast<std::size_t>(std::clamp(
      std::ceil(q * static_cast<double>(sorted.size())), 1.0, static_cast<double>(sorted.size())));
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<long>(rank - 1), sorted.end());
  return sorted[rank - 1];
}

std::string LatencyStats::summary(const std::string& name) const {
  return fmt::format("{:<12} p50 {:7.3f} ms  p99 {:7.3f} ms  ({} frames)", name, quantile(0.5),
                     quantile(0.99), total_);
}

}  // namespace rostro::live
