#include "capture/sequence_counter.hpp"

#include <gtest/gtest.h>

namespace rostro::capture {
namespace {

TEST(SequenceCounter, CountsGapsAsDroppedFrames) {
  SequenceCounter counter;
  EXPECT_EQ(counter.observe(100), 0);  // the first number only sets the origin
  EXPECT_EQ(counter.relative(), 0);
  EXPECT_EQ(counter.observe(101), 0);
  EXPECT_EQ(counter.observe(104), 2);  // 102 and 103 lost
  EXPECT_EQ(counter.relative(), 4);
  EXPECT_EQ(counter.observe(105), 0);
  EXPECT_EQ(counter.dropped(), 2);
}

TEST(SequenceCounter, RestartDoesNotCountAsLoss) {
  SequenceCounter counter;
  counter.observe(7);
  counter.observe(8);
  EXPECT_EQ(counter.observe(0), 0);  // driver restarted its counter
  EXPECT_EQ(counter.relative(), 2);  // still increasing for the consumer
  EXPECT_EQ(counter.observe(2), 1);
  EXPECT_EQ(counter.relative(), 4);
  EXPECT_EQ(counter.dropped(), 1);
}

}  // namespace
}  // namespace rostro::capture
