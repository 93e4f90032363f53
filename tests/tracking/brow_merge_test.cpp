// An inner brow dot sits at the eyebrow's inner end. As the head turns, the eyebrow's hair
// (nearly as dark as the ink) comes to touch the dot's outer side and merges with it at every
// share of its contrast: the merged blob's centre, and its edge, lie a pixel or two out along
// the eyebrow. On the rendered head that was the squeezed brows' error under turns (closed loop
// 640x480: squeeze_eyebrow 14 % of range). The tracker must keep the dot where it is.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "tests/support/drawn_layout.hpp"
#include "tracking/layout.hpp"
#include "tracking/marker_tracker.hpp"

namespace rostro::tracking {
namespace {

using testing::draw_disc;
using testing::fixed_point;
using testing::start_on_drawing;

constexpr double kPxPerMm = 2.4;
constexpr int kFrames = 30;

// The face's own motion in frame k, pixels: the dot and the eyebrow move together.
cv::Point2d face_shift(int k) {
  return {2.5 * std::sin(0.35 * k), 1.5 * std::sin(0.23 * k)};
}

cv::Point2d to_image(cv::Point2d mm, int k) {
  return cv::Point2d(320 + mm.x * kPxPerMm, 230 + mm.y * kPxPerMm) + face_shift(k);
}

// Frame k: flat skin, every dot of the layout at its frontal place, and the left eyebrow: a band
// wider than a dot running 24 mm outward from brow_l_in, nearly as dark as the ink at its inner
// end and lighter outward, whose inner end closes on the dot (2 px from its rim at the start,
// 0.7 px under it from frame 6 on, as a turn foreshortens the skin between them; or under it
// from the start). Returns brow_l_in's truth.
cv::Point2d render(const MarkerLayout& layout, int k, cv::Mat& img,
                   bool merged_from_start = false) {
  img = cv::Mat(480, 640, CV_8UC1, cv::Scalar(180));
  const MarkerSpec* inner = nullptr;
  for (const MarkerSpec& m : layout.markers)
    if (m.id == "brow_l_in") inner = &m;
  const double radius_px = layout.dot_diameter_mm / 2 * kPxPerMm;
  const cv::Point2d centre = to_image(inner->frontal(), k);
  const double gap_px =
      merged_from_start ? -0.15 * radius_px : std::max(-0.15 * radius_px, 2.0 - 0.5 * k);
  const double half_width = 1.3 * radius_px;
  // Darkest (nearly the ink) at its inner end, lighter outward: a steady grey ramp of bands,
  // each shorter and darker than the last.
  for (int grey = 100; grey >= 35; grey -= 5) {
    const double x0 = centre.x + radius_px + gap_px;
    const double x1 =
        x0 + std::max(1.5, (grey - 35) / 65.0 * 2.5 * kPxPerMm) + (grey == 100 ? 21 * kPxPerMm : 0);
    const std::vector<cv::Point> band = {
        fixed_point({x0, centre.y - half_width}), fixed_point({x1, centre.y - half_width}),
        fixed_point({x1, centre.y + half_width}), fixed_point({x0, centre.y + half_width})};
    cv::fillConvexPoly(img, band, cv::Scalar(grey), cv::LINE_AA, 4);
  }
  for (const MarkerSpec& m : layout.markers) {
    if (m.is_tag()) continue;
    draw_disc(img, to_image(m.frontal(), k), radius_px, 25);
  }
  cv::GaussianBlur(img, img, {0, 0}, 0.7);
  return centre;
}

struct BrowTrack {
  std::vector<double> dx;  // tracked - true x per frame, NaN while reported lost
};

BrowTrack track_brow(const TrackerOptions& options, bool merged_from_start = false) {
  const MarkerLayout layout =
      load_layout(std::filesystem::path(ROSTRO_DATA_DIR) / "layouts" / "default.json");
  MarkerTracker tracker(layout, options);
  // Started from the drawn places (a flat drawing is no face for automatic identification).
  start_on_drawing(tracker, layout, [&](const MarkerSpec& m) { return to_image(m.frontal(), 0); });
  BrowTrack out;
  for (int k = 0; k < kFrames; ++k) {
    cv::Mat img;
    const cv::Point2d truth = render(layout, k, img, merged_from_start);
    const TrackedFrame f = tracker.track(img, k, k / 25.0);
    for (const MarkerObservation& o : f.markers)
      if (o.marker == "brow_l_in")
        out.dx.push_back(o.valid ? o.position.x - truth.x : std::nan(""));
  }
  return out;
}

TEST(BrowMerge, InnerBrowDotAgainstTheEyebrowStaysInPlace) {
  // Placed by its ink's core while merged (0.7 px toward the band here, see kInkBound; LK alone
  // was pulled as far by the eyebrow's end sliding into its window), where the merged blob is
  // 2-3 px out.
  const BrowTrack t = track_brow({});
  ASSERT_EQ(t.dx.size(), static_cast<size_t>(kFrames));
  int followed = 0;
  for (size_t k = 0; k < t.dx.size(); ++k) {
    if (std::isnan(t.dx[k])) continue;
    ++followed;
    EXPECT_LT(std::abs(t.dx[k]), 0.8) << "frame " << k << ": measured with the eyebrow";
  }
  EXPECT_GE(followed, kFrames - 2) << "the dot should be followed, not dropped";
}

TEST(BrowMerge, MeasuredOnTheMergedBlobItIsPixelsOut) {
  // The same take measuring the merged blob as it is (what the option guards against): the
  // centre moves out along the eyebrow, so the scene does test the merge.
  TrackerOptions o;
  o.brows.hold_merged_inner_brows = false;
  const BrowTrack t = track_brow(o);
  double worst = 0;
  for (double d : t.dx)
    if (!std::isnan(d)) worst = std::max(worst, d);
  EXPECT_GT(worst, 1.5);
}

// Held where LK moves it, a dot measured on the merged blob once (merged at the start, or found
// again merged after a loss) stayed that far out for as long as it was held (the closed loop's
// turns at 640x480: 1.7 px for 20 frames). Its ink's core places it, leaning
// toward the band here by up to 0.7 px: the band's end is only 6 % of the contrast lighter than
// the ink (on the rendered head the eyebrow is 10-30 % lighter, the core 0.25 px RMS off).
constexpr double kInkBound = 0.85;
TEST(BrowMerge, MergedAtTheStartItIsPlacedOnItsInk) {
  const BrowTrack t = track_brow({}, /*merged_from_start=*/true);
  int followed = 0;
  for (size_t k = 0; k < t.dx.size(); ++k) {
    if (std::isnan(t.dx[k])) continue;
    ++followed;
    EXPECT_LT(std::abs(t.dx[k]), kInkBound) << "frame " << k << ": measured with the eyebrow";
  }
  EXPECT_GE(followed, kFrames - 2) << "the dot should be followed, not dropped";
}

}  // namespace
}  // namespace rostro::tracking
