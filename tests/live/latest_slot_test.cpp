#include "live/latest_slot.hpp"

#include <gtest/gtest.h>

#include <thread>

namespace rostro::live {
namespace {

TEST(LatestSlot, NewestItemWinsAndSkipsAreCounted) {
  LatestSlot<int> slot;
  slot.put(1);
  slot.put(2);
  slot.put(3);
  EXPECT_EQ(slot.take(), 3);
  EXPECT_EQ(slot.skipped(), 2);
}

TEST(LatestSlot, CloseDrainsThenEnds) {
  LatestSlot<int> slot;
  slot.put(5);
  slot.close();
  EXPECT_EQ(slot.take(), 5);
  EXPECT_EQ(slot.take(), std::nullopt);
}

TEST(LatestSlot, ConsumerThreadSeesIncreasingItemsAndTheLast) {
  LatestSlot<int> slot;
  std::vector<int> seen;
  std::thread consumer([&] {
    while (auto item = slot.take()) seen.push_back(*item);
  });
  for (int i = 1; i <= 1000; ++i) slot.put(i);
  slot.close();
  consumer.join();
  ASSERT_FALSE(seen.empty());
  EXPECT_EQ(seen.back(), 1000);
  for (std::size_t i = 1; i < seen.size(); ++i) EXPECT_LT(seen[i - 1], seen[i]);
  EXPECT_EQ(static_cast<std::int64_t>(seen.size()) + slot.skipped(), 1000);
}

}  // namespace
}  // namespace rostro::live
