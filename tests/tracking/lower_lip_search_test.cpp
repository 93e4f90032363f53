// The lower lip's joint search on its own (tracking/lower_lip_search.hpp), on a drawing: the
// mouth turned, grown and shifted, the lower lip opened down by one and a half spacings, and a
// lone dark blob (the open mouth's corner) inside the strip one dot is looked for in. The dots
// are found by the real dot detector; the lip must be found where it is drawn, and the blob
// never taken.

#include "tracking/lower_lip_search.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <vector>

#include "tracking/affine2d.hpp"
#include "tracking/dot_detector.hpp"

namespace rostro::tracking::internal {
namespace {

void disc(cv::Mat& image, cv::Point2d centre, double radius, int grey) {
  constexpr int kShift = 4;  // sub-pixel centres and radii
  const double k = 1 << kShift;
  cv::circle(image, cv::Point(static_cast<int>(centre.x * k), static_cast<int>(centre.y * k)),
             static_cast<int>(radius * k), cv::Scalar(grey), cv::FILLED, cv::LINE_AA, kShift);
}

constexpr double kSpacing = 20;

// The mouth's motion since the start: turned 8 degrees, 1.1 times larger, shifted.
cv::Matx23d mouth_motion() {
  const double angle = 8 * CV_PI / 180, k = 1.1;
  const double c = k * std::cos(angle), s = k * std::sin(angle);
  const cv::Point2d centre(320, 310), shift(6, -4);
  return {c, -s, centre.x + shift.x - (c * centre.x - s * centre.y),
          s, c,  centre.y + shift.y - (s * centre.x + c * centre.y)};
}

struct MouthDrawing {
  // At the start: the upper lip and the corners, and the lower lip's three dots.
  std::vector<cv::Point2d> upper_start{{270, 312}, {295, 306}, {320, 304}, {345, 306}, {370, 312}};
  std::vector<cv::Point2d> lower_start{{300, 326}, {320, 330}, {340, 326}};
  cv::Point2d opened{0, 30};       // the lower lip's motion in the mouth's frame, start pixels
  cv::Point2d blob_offset{6, 12};  // the lone blob from the middle dot's start place, likewise
  cv::Matx23d motion = mouth_motion();
  cv::Mat image = cv::Mat(480, 640, CV_8UC1, cv::Scalar(200));

  cv::Point2d lower_now(size_t k) const { return apply(motion, lower_start[k] + opened); }
  cv::Point2d blob_now() const { return apply(motion, lower_start[1] + blob_offset); }

  // Draws the upper lip, the lower-lip dots listed, and the blob when asked.
  void draw(const std::vector<size_t>& lower, bool blob) {
    for (const cv::Point2d& p : upper_start) disc(image, apply(motion, p), 4, 25);
    for (size_t k : lower) disc(image, lower_now(k), 4, 25);
    if (blob) disc(image, blob_now(), 4.5, 20);
    cv::GaussianBlur(image, image, {0, 0}, 0.7);
  }

  // The scene as the tracker hands it over: markers 0-4 the upper lip, 5-7 the lower lip.
  LowerLipScene scene(const std::vector<size_t>& followed_lower) const {
    LowerLipScene s;
    for (size_t j = 0; j < upper_start.size(); ++j) {
      const cv::Point2d now = apply(motion, upper_start[j]);
      s.upper_start.push_back(upper_start[j]), s.upper_now.push_back(now);
      s.followed.push_back({j, now, kSpacing});
    }
    for (size_t k = 0; k < lower_start.size(); ++k) {
      const bool followed =
          std::find(followed_lower.begin(), followed_lower.end(), k) != followed_lower.end();
      const size_t marker = upper_start.size() + k;
      s.lower_lip.push_back({marker, lower_start[k], kSpacing, followed,
                             followed ? lower_now(k) : cv::Point2d(), !followed});
      if (followed) s.followed.push_back({marker, lower_now(k), kSpacing});
    }
    return s;
  }

  LowerLipSearch search() const {
    LowerLipSearch s;
    s.dots_near = [this](size_t, cv::Point2d centre, double radius) {
      return dots_near(image, centre, radius, DotOptions{}, 4, 0);
    };
    s.passes = [](size_t, const Dot&) { return true; };
    return s;
  }
};

TEST(LowerLipSearch, MouthFrameIsTheUpperLipsSimilarity) {
  MouthDrawing m;
  const auto frame = mouth_frame(m.upper_start, m.scene({}).upper_now);
  ASSERT_TRUE(frame.has_value());
  for (int r = 0; r < 2; ++r)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR((*frame)(r, c), m.motion(r, c), 1e-9);
  EXPECT_FALSE(mouth_frame({{1, 2}}, {{3, 4}}).has_value()) << "one point gives no frame";
}

TEST(LowerLipSearch, FindsTheOpenedLipTogetherAndNotTheBlob) {
  MouthDrawing m;
  m.draw({0, 1, 2}, true);
  const std::vector<Dot> at_blob = dots_near(m.image, m.blob_now(), 2, DotOptions{});
  ASSERT_FALSE(at_blob.empty()) << "the blob must look like a dot, or the test checks nothing";
  const auto found = find_lower_lip(m.scene({}), m.search());
  ASSERT_TRUE(found.has_value());
  ASSERT_EQ(found->size(), 3u);
  for (const LowerLipFound& f : *found) {
    const size_t k = f.marker - m.upper_start.size();
    ASSERT_LT(k, 3u);
    EXPECT_LT(cv::norm(f.dot.center - m.lower_now(k)), 0.5) << "lower-lip dot " << k;
  }
}

TEST(LowerLipSearch, AFollowedDotGuidesTheOthers) {
  MouthDrawing m;
  m.draw({0, 1, 2}, true);
  const auto found = find_lower_lip(m.scene({0}), m.search());
  ASSERT_TRUE(found.has_value());
  ASSERT_EQ(found->size(), 2u);
  for (const LowerLipFound& f : *found) {
    const size_t k = f.marker - m.upper_start.size();
    ASSERT_TRUE(k == 1 || k == 2) << "marker " << f.marker;
    EXPECT_LT(cv::norm(f.dot.center - m.lower_now(k)), 0.5) << "lower-lip dot " << k;
  }
}

TEST(LowerLipSearch, ALoneDotOrBlobIsNotTaken) {
  MouthDrawing m;
  m.draw({1}, true);  // the middle dot alone beside the blob: no two dots share a shift
  const auto found = find_lower_lip(m.scene({}), m.search());
  ASSERT_TRUE(found.has_value()) << "searched: the lip's dots are lost";
  EXPECT_TRUE(found->empty());
}

TEST(LowerLipSearch, ADotWhereALostNeighbourIsExpectedIsNotTaken) {
  // The middle dot curled under the lip and not seen; the chin boss's dot just below where it
  // would be, the chin boss itself lost for the frame and expected there.
  MouthDrawing m;
  const cv::Point2d chin_boss = apply(m.motion, m.lower_start[1] + m.opened + cv::Point2d(0, 6));
  disc(m.image, chin_boss, 4, 25);
  m.draw({0, 2}, false);
  LowerLipScene scene = m.scene({0, 2});
  const auto unaware = find_lower_lip(scene, m.search());
  ASSERT_TRUE(unaware.has_value() && unaware->size() == 1u &&
              cv::norm(unaware->front().dot.center - chin_boss) < 0.5)
      << "without the chin boss expected there its dot is taken, or the test checks nothing";
  scene.expected.push_back({8, chin_boss, kSpacing});
  const auto found = find_lower_lip(scene, m.search());
  ASSERT_TRUE(found.has_value()) << "searched: the middle dot is lost";
  EXPECT_TRUE(found->empty());
}

TEST(LowerLipSearch, NotSearchedWhenNoneIsLost) {
  MouthDrawing m;
  m.draw({0, 1, 2}, false);
  EXPECT_FALSE(find_lower_lip(m.scene({0, 1, 2}), m.search()).has_value());
}

}  // namespace
}  // namespace rostro::tracking::internal
