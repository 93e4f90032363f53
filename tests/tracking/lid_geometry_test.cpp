// The eye's dots told apart, each lid dot's eye corners, and a point's place relative to the
// line through them (tracking/lid_geometry.hpp).
#include "tracking/lid_geometry.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace rostro::tracking::internal {
namespace {

// A layout's markers in an order of their own: a brow dot, the left eye's upper lid, outer and
// inner corners, the right eye's upper lid and inner corner only (its outer corner unmarked).
const std::vector<FeaturePointId> kPoints = {{4, 1}, {3, 1}, {3, 7}, {3, 11}, {3, 2}, {3, 8}};
constexpr size_t kBrow = 0, kLeftLid = 1, kLeftOuter = 2, kLeftInner = 3, kRightLid = 4;

// Start positions in pixels (y down): the left eye's corners level, its upper lid 10 px above.
const std::vector<cv::Point2d> kStart = {{300, 150}, {350, 190}, {380, 200},
                                         {320, 200}, {250, 190}, {280, 200}};

TEST(LidGeometryTest, TellsTheEyeDotsApart) {
  EXPECT_TRUE(is_eye_point({3, 12}));
  EXPECT_FALSE(is_eye_point({4, 1}));
  for (int index = 1; index <= 4; ++index) EXPECT_TRUE(is_lid_point({3, index}));
  EXPECT_FALSE(is_lid_point({3, 5}));
  EXPECT_FALSE(is_lid_point({4, 1}));
  EXPECT_TRUE(is_inner_eye_corner({3, 8}));
  EXPECT_TRUE(is_inner_eye_corner({3, 11}));
  EXPECT_FALSE(is_inner_eye_corner({3, 7}));
  EXPECT_FALSE(is_inner_eye_corner({3, 12}));
}

TEST(LidGeometryTest, FindsEachLidsCornersInTheLayout) {
  const LidGeometry lids(kPoints);
  ASSERT_TRUE(lids.corners(kLeftLid).has_value());
  EXPECT_EQ(lids.corners(kLeftLid)->first, kLeftInner);
  EXPECT_EQ(lids.corners(kLeftLid)->second, kLeftOuter);
  EXPECT_FALSE(lids.corners(kRightLid).has_value()) << "its outer corner has no marker";
  EXPECT_FALSE(lids.corners(kBrow).has_value());
  EXPECT_FALSE(lids.corners(kLeftInner).has_value());
}

TEST(LidGeometryTest, AxisFollowsTheMapFromTheStart) {
  const LidGeometry lids(kPoints);
  // A quarter turn (image x -> y) and a doubling: the axis turns and keeps unit length.
  const cv::Matx23d turn(0, -2, 5, 2, 0, 7);
  const auto axis = lids.axis(kLeftLid, kStart, turn);
  ASSERT_TRUE(axis.has_value());
  EXPECT_NEAR(axis->x, 0, 1e-12);
  EXPECT_NEAR(axis->y, 1, 1e-12);
  EXPECT_FALSE(lids.axis(kRightLid, kStart, turn).has_value());
}

}  // namespace
}  // namespace rostro::tracking::internal
