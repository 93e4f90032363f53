#include "live/latency_stats.hpp"

#include <gtest/gtest.h>

namespace rostro::live {
namespace {

TEST(LatencyStats, NearestRankQuantiles) {
  LatencyStats stats;
  for (int i = 100; i >= 1; --i) stats.add(i);  // 1..100 ms in any order
  EXPECT_DOUBLE_EQ(stats.quantile(0.5), 50);
  EXPECT_DOUBLE_EQ(stats.quantile(0.99), 99);
  EXPECT_DOUBLE_EQ(stats.quantile(1.0), 100);
  EXPECT_EQ(stats.count(), 100u);
  EXPECT_NE(stats.summary("fit").find("p99"), std::string::npos);
}

TEST(LatencyStats, WindowKeepsTheRecentSamples) {
  LatencyStats stats(10);
  for (int i = 0; i < 10; ++i) stats.add(1000);
  for (int i = 0; i < 10; ++i) stats.add(1);
  EXPECT_DOUBLE_EQ(stats.quantile(0.99), 1);
  EXPECT_EQ(stats.count(), 20u);
  EXPECT_DOUBLE_EQ(LatencyStats().quantile(0.5), 0);
}

}  // namespace
}  // namespace rostro::live
