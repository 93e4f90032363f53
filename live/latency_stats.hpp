#pragma once
// Per-stage timing for the live pipeline: samples in milliseconds, summarised as p50 and
// p99. Keeps the most recent samples only, so a long session's figures describe now.

#include <cstddef>
#include <string>
#include <vector>

namespace rostro::live {

class LatencyStats {
 public:
  explicit LatencyStats(std::size_t window = 4096) : window_(window) {}
  void add(double ms);
  std::size_t count() const { return total_; }
  // The q-quantile (0..1) of the samples in the window, by nearest rank; 0 with none.
  double quantile(double q) const;
  std::string summary(const std::string& name) const;  // "fit  p50 0.31 ms  p99 0.52 ms"

 private:
  std::size_t window_;
  std::vector<double> samples_;
  std::size_t next_ = 0;
  std::size_t total_ = 0;
};

}  // namespace rostro::live
