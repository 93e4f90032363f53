// The eye dots where the rendered head puts them at 1280x720 and under head turns: an inner
// eye-corner dot with the eye slit's thin corner line running into it, and a lid dot merged
// with the pupil into one tall blob.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "tests/support/drawn_layout.hpp"
#include "tracking/dot_detector.hpp"
#include "tracking/layout.hpp"
#include "tracking/marker_tracker.hpp"

namespace rostro::tracking {
namespace {

using testing::fixed_point;
using testing::start_on_drawing;

constexpr double kPxPerMm = 3.0;  // 4 mm dots 12 px wide, as the eye dots at 1280x720 (9-12)
constexpr int kSkin = 180, kInk = 25, kLine = 60;

// Frontal layout millimetres (x right, y down) to pixels.
cv::Point2d to_image(cv::Point2d mm) {
  return {320 + mm.x * kPxPerMm, 230 + mm.y * kPxPerMm};
}

void ellipse(cv::Mat& img, cv::Point2d c, cv::Size2d semi_axes, int grey) {
  cv::ellipse(img, fixed_point(c),
              cv::Size(cvRound(semi_axes.width * 16), cvRound(semi_axes.height * 16)), 0, 0, 360,
              cv::Scalar(grey), cv::FILLED, cv::LINE_AA, 4);
}

MarkerLayout default_layout() {
  return load_layout(std::filesystem::path(ROSTRO_DATA_DIR) / "layouts" / "default.json");
}

// Every dot of the layout on flat skin, with the face's eyes: between each eye's corner
// dots a light slit whose inner corner runs out in a thin dark line into the inner corner dot
// (as the rendered head's lash line does at 1280x720), and an iris and pupil between the lid
// dots. The corner
// dots are seen at an angle (taller than wide), as on the head. `left` changes the left eye.
struct LeftEye {
  bool upper_lid_seen = true;
  double upper_lid_width = 1;        // of the dot's height: less is a lid seen at an angle
  double pupil_down_px = 0;          // from the eye's centre
  double pupil_radius = 0.9;         // of the dot's
  double inner_corner_width = 0.85;  // of the inner corner dot's height
};
cv::Mat draw_face(const MarkerLayout& layout, const LeftEye& left = {}) {
  cv::Mat img(480, 640, CV_8UC1, cv::Scalar(kSkin));
  std::map<std::string, cv::Point2d> at;
  for (const MarkerSpec& m : layout.markers)
    if (!m.is_tag()) at[m.id] = to_image(m.frontal());
  const double r = layout.dot_diameter_mm / 2 * kPxPerMm;
  for (const char* side : {"l", "r"}) {
    const std::string s = side;
    const cv::Point2d in = at["eye_" + s + "_in"], out = at["eye_" + s + "_out"];
    const cv::Point2d up = at["lid_" + s + "_up"], low = at["lid_" + s + "_low"];
    const cv::Point2d centre = (in + out) * 0.5;
    // The slit: light, from just outside each corner dot to the lids.
    const double tip = 1.8 * r;
    const cv::Point2d toward_out = (out - in) * (1.0 / cv::norm(out - in));
    std::vector<cv::Point> slit = {
        fixed_point(in + toward_out * tip), fixed_point(up + cv::Point2d(0, r)),
        fixed_point(out - toward_out * tip), fixed_point(low - cv::Point2d(0, r))};
    cv::fillConvexPoly(img, slit, cv::Scalar(225), cv::LINE_AA, 4);
    // The corner line: one pixel, dark, from the inner corner dot to the slit's tip.
    cv::line(img, fixed_point(in), fixed_point(in + toward_out * tip), cv::Scalar(kLine), 1,
             cv::LINE_AA, 4);
    const LeftEye eye = s == "l" ? left : LeftEye{};
    ellipse(img, centre, {2.2 * r, 2.2 * r}, 110);  // iris
    const double pupil = eye.pupil_radius * r;
    ellipse(img, centre + cv::Point2d(0, eye.pupil_down_px), {pupil, pupil}, kInk);
  }
  for (const MarkerSpec& m : layout.markers) {
    if (m.is_tag()) continue;
    const bool corner = m.feature_point.group == 3 && m.feature_point.index > 4;
    if (m.id == "lid_l_up") {
      if (left.upper_lid_seen) ellipse(img, at[m.id], {left.upper_lid_width * r, r}, kInk);
      continue;
    }
    const double width = m.id == "eye_l_in" ? left.inner_corner_width : 0.85;
    ellipse(img, at[m.id], corner ? cv::Size2d(width * r, r) : cv::Size2d(r, r), kInk);
  }
  cv::GaussianBlur(img, img, {0, 0}, 0.5);
  return img;
}

// The eye dots' tracks over `frames` frames of one drawing (the start at the drawn places).
std::vector<std::map<std::string, MarkerObservation>> track_still(const cv::Mat& img, int frames,
                                                                  const TrackerOptions& options) {
  const MarkerLayout layout = default_layout();
  MarkerTracker tracker(layout, options);
  start_on_drawing(tracker, layout, [&](const MarkerSpec& m) { return to_image(m.frontal()); });
  std::vector<std::map<std::string, MarkerObservation>> out;
  for (int k = 0; k < frames; ++k) {
    std::map<std::string, MarkerObservation> f;
    for (const MarkerObservation& o : tracker.track(img, k, k / 25.0).markers) f[o.marker] = o;
    out.push_back(f);
  }
  return out;
}

TEST(EyeDots, InnerCornerWithTheSlitsLineRunningIntoItIsFollowed) {
  const MarkerLayout layout = default_layout();
  const cv::Mat img = draw_face(layout);
  const auto run = track_still(img, 6, {});
  for (size_t k = 0; k < run.size(); ++k)
    for (const char* id : {"eye_l_in", "eye_r_in", "eye_l_out", "eye_r_out"}) {
      const MarkerObservation& o = run[k].at(id);
      ASSERT_TRUE(o.valid) << "frame " << k << ": " << id << " lost";
      for (const MarkerSpec& m : layout.markers) {
        if (m.id != id) continue;
        EXPECT_LT(cv::norm(o.position - to_image(m.frontal())), 0.3) << "frame " << k << ": " << id;
      }
    }
}

TEST(EyeDots, LineRaisesTheShareOnlyWhenAsked) {
  const MarkerLayout layout = default_layout();
  const cv::Mat img = draw_face(layout);
  cv::Point2d inner;
  for (const MarkerSpec& m : layout.markers)
    if (m.id == "eye_l_in") inner = to_image(m.frontal());
  DotOptions plain;  // rejected as not round: the line makes the blob at half reach far
  EXPECT_FALSE(refine_dot(img, inner, 2, plain).has_value());
  DotOptions raised;
  raised.raise_share_for_roundness = true;
  const auto dot = refine_dot(img, inner, 2, raised);
  ASSERT_TRUE(dot.has_value());
  EXPECT_LT(cv::norm(dot->center - inner), 0.3);
}

// The inner corner seen steeply (the head turned away from it): a blob more than 3 times as
// tall as wide, which large dots (12 px here, as at 1280x720) may be
// (EyeOptions::inner_corner_max_elongation_large); held to the general 3 it is lost.
TEST(EyeDots, SteeplySeenInnerCornerOfLargeDotsIsKept) {
  const MarkerLayout layout = default_layout();
  LeftEye steep;
  steep.inner_corner_width = 0.24;
  const cv::Mat frontal = draw_face(layout), turned = draw_face(layout, steep);
  cv::Point2d inner;
  for (const MarkerSpec& m : layout.markers)
    if (m.id == "eye_l_in") inner = to_image(m.frontal());
  DotOptions measure;
  measure.raise_share_for_roundness = true;
  measure.max_elongation = 10;
  const auto dot = refine_dot(turned, inner, 2, measure);
  ASSERT_TRUE(dot.has_value());
  ASSERT_GT(dot->elongation, 3.0) << "the drawing is not steep enough to test the limit";
  ASSERT_LT(dot->elongation, 4.0);

  // Started on the frontal face, then the corner turning steep over eight frames (as a head
  // turning at about 100 degrees a second: a dot that shrinks much faster is dropped,
  // TrackerOptions::min_recent_size), then held there.
  auto inner_corner_after_turn = [&](const TrackerOptions& options) {
    MarkerTracker tracker(layout, options);
    start_on_drawing(tracker, layout, [&](const MarkerSpec& m) { return to_image(m.frontal()); });
    MarkerObservation last;
    for (int k = 0; k < 14; ++k) {
      LeftEye turning;
      const double t = std::clamp((k - 1) / 8.0, 0.0, 1.0);
      turning.inner_corner_width = (1 - t) * LeftEye().inner_corner_width + t * 0.24;
      const cv::Mat image = k < 2 ? frontal : k >= 9 ? turned : draw_face(layout, turning);
      for (const MarkerObservation& o : tracker.track(image, k, k / 25.0).markers)
        if (o.marker == "eye_l_in") last = o;
    }
    return last;
  };
  const MarkerObservation kept = inner_corner_after_turn({});
  ASSERT_TRUE(kept.valid);
  EXPECT_LT(cv::norm(kept.position - inner), 0.3);
  TrackerOptions general;
  general.eyes.inner_corner_max_elongation_large = 3;
  EXPECT_FALSE(inner_corner_after_turn(general).valid);
}

// The upper lid's dot hidden for a few frames, then seen again narrowed (the head turned) with
// the pupil right under it: they merge into one blob about the dot's size at the start, but
// twice as tall as wide, whose centre is pixels below the dot's (the closed loop's joy with
// head turns: 2.5-3 px, for 20 frames). The dot must be
// reported lost while merged, never measured there.
TEST(EyeDots, LidDotFoundMergedWithThePupilIsNotTaken) {
  const MarkerLayout layout = default_layout();
  MarkerTracker tracker(layout, {});
  std::map<std::string, cv::Point2d> start;
  for (const MarkerSpec& m : layout.markers)
    if (!m.is_tag()) start[m.id] = to_image(m.frontal());
  tracker.set_start_positions(start);
  const cv::Point2d lid = start["lid_l_up"];
  const double r = layout.dot_diameter_mm / 2 * kPxPerMm;
  const double eye_y = 0.5 * (start["eye_l_in"].y + start["eye_l_out"].y);
  LeftEye merged;
  merged.upper_lid_width = 0.6;
  merged.pupil_radius = 0.5;
  merged.pupil_down_px = lid.y + 1.2 * r - eye_y;  // overlapping the dot's rim by 0.3 r
  LeftEye hidden = merged;
  hidden.upper_lid_seen = false;
  bool seen_before = false;
  for (int k = 0; k < 16; ++k) {
    const cv::Mat img = draw_face(layout, k < 5 ? LeftEye{} : k < 8 ? hidden : merged);
    for (const MarkerObservation& o : tracker.track(img, k, k / 25.0).markers) {
      if (o.marker != "lid_l_up") continue;
      if (k == 4) seen_before = o.valid;
      if (k >= 8 && o.valid) {
        EXPECT_LT(cv::norm(o.position - lid), 1.0) << "frame " << k << ": measured with the pupil";
      }
    }
  }
  EXPECT_TRUE(seen_before);
}

}  // namespace
}  // namespace rostro::tracking
