// The eye's dots told apart and the eye rules' ranges (tracking/eye_options.hpp).
#include "tracking/eye_options.hpp"

#include <gtest/gtest.h>

#include "facecore/error.hpp"

namespace rostro::tracking::internal {
namespace {

TEST(EyeOptionsTest, TellsTheEyeDotsApart) {
  EXPECT_TRUE(is_eye_point({3, 12}));
  EXPECT_FALSE(is_eye_point({4, 1}));
  for (int index = 1; index <= 4; ++index) EXPECT_TRUE(is_eyelid_midpoint({3, index}));
  EXPECT_FALSE(is_eyelid_midpoint({3, 5}));
  EXPECT_FALSE(is_eyelid_midpoint({4, 1}));
  EXPECT_TRUE(is_inner_eye_corner({3, 8}));
  EXPECT_TRUE(is_inner_eye_corner({3, 11}));
  EXPECT_FALSE(is_inner_eye_corner({3, 7}));
  EXPECT_FALSE(is_inner_eye_corner({3, 12}));
}

TEST(EyeOptionsTest, RejectsAnOutOfRangeRule) {
  EXPECT_NO_THROW(EyeOptions{}.validate());
  EyeOptions o;
  o.max_lid_elongation = 0.5;
  EXPECT_THROW(o.validate(), InputError);
  o = {};
  o.eye_size_memory_frames = -1;
  EXPECT_THROW(o.validate(), InputError);
}

}  // namespace
}  // namespace rostro::tracking::internal
