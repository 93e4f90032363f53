// A dot on a dark patch of the face that is no pupil: the middle lower-lip dot in the shadow
// under the lower lip (the photo scenes: a real face's labiomental fold), ringed by it as
// darkly as a pupil is by its iris. The tracker keeps the dark-ring test
// (DotOptions::max_surround) for the dots of the eyes, the brows and the nose, where the pupil
// and the nostrils are (TrackerOptions::surround_test_upper_face_only): the lower lip's dot is
// followed through the shadow, where the test for every dot loses it.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <opencv2/imgproc.hpp>

#include "tests/support/drawn_layout.hpp"
#include "tracking/layout.hpp"
#include "tracking/marker_tracker.hpp"

namespace rostro::tracking {
namespace {

using testing::draw_disc;
using testing::fixed_point;
using testing::start_on_drawing;

constexpr double kPxPerMm = 3.0;  // dots 12 px wide
constexpr int kFrames = 30;
constexpr char kMarker[] = "lip_bot";

cv::Point2d to_image(cv::Point2d mm, int k) {
  const cv::Point2d drift(1.5 * std::sin(0.23 * k), 1.0 * std::sin(0.19 * k));
  return cv::Point2d(320 + mm.x * kPxPerMm, 200 + mm.y * kPxPerMm) + drift;
}

// Frame k: flat skin, the layout's dots at their frontal places, and around lip_bot a shadow
// (a soft dark ellipse as wide as the lower lip) that darkens over the first ten frames.
// Returns lip_bot's truth.
cv::Point2d render(const MarkerLayout& layout, int k, cv::Mat& img) {
  img = cv::Mat(480, 640, CV_8UC1, cv::Scalar(180));
  const cv::Point2d centre = to_image(layout.find(kMarker)->frontal(), k);
  const double radius_px = layout.dot_diameter_mm / 2 * kPxPerMm;
  cv::Mat shadow(img.size(), CV_8UC1, cv::Scalar(0));
  cv::ellipse(shadow, fixed_point(centre),
              cv::Size(cvRound(4 * radius_px * 16), cvRound(2.2 * radius_px * 16)), 0, 0, 360,
              cv::Scalar(255), cv::FILLED, cv::LINE_AA, testing::kDrawShift);
  cv::GaussianBlur(shadow, shadow, {0, 0}, radius_px / 2);
  const double depth = 110.0 * std::min(1.0, k / 10.0) / 255.0;  // grey levels at its middle
  img -= shadow * depth;
  for (const MarkerSpec& m : layout.markers)
    if (!m.is_tag()) draw_disc(img, to_image(m.frontal(), k), radius_px, 25);
  cv::GaussianBlur(img, img, {0, 0}, 0.7);
  return centre;
}

// The frames lip_bot was followed within 0.3 px of its truth.
int followed(const TrackerOptions& options) {
  const MarkerLayout layout =
      load_layout(std::filesystem::path(ROSTRO_DATA_DIR) / "layouts" / "default.json");
  MarkerTracker tracker(layout, options);
  start_on_drawing(tracker, layout, [&](const MarkerSpec& m) { return to_image(m.frontal(), 0); });
  int count = 0;
  for (int k = 0; k < kFrames; ++k) {
    cv::Mat img;
    const cv::Point2d truth = render(layout, k, img);
    for (const MarkerObservation& o : tracker.track(img, k, k / 25.0).markers)
      count += o.marker == kMarker && o.valid && cv::norm(o.position - truth) < 0.3;
  }
  return count;
}

TEST(ShadowedDot, ALowerLipDotInTheLipsShadowIsFollowed) {
  EXPECT_EQ(followed(TrackerOptions{}), kFrames);
  // The dark-ring test for every dot takes it for a pupil once the shadow is dark.
  TrackerOptions everywhere;
  everywhere.surround_test_upper_face_only = false;
  EXPECT_LT(followed(everywhere), kFrames - 10);
}

}  // namespace
}  // namespace rostro::tracking
