// Lid dots lost and found again, on flat drawings of the layout whose eye dots drift away from
// their neighbours as a turned head's eyes do (they sit at another depth).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <map>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <string>
#include <vector>

#include "tests/support/drawn_layout.hpp"
#include "tracking/layout.hpp"
#include "tracking/marker_tracker.hpp"

namespace rostro::tracking {
namespace {

using testing::draw_and_track;
using testing::DrawnRun;
using testing::start_on_drawing;

// Frontal layout millimetres (x right, y down) to pixels, `scale` pixels a millimetre, in an
// image of 640x480 at 2.4 and in proportion.
cv::Point2d to_image(cv::Point2d mm, double scale = 2.4) {
  return cv::Point2d(320, 230) * (scale / 2.4) + mm * scale;
}

bool left_eye(const MarkerSpec& m) {
  return m.feature_point.group == 3 && m.feature_point.index % 2 == 1;
}

// Where each dot is in frame k (frontal millimetres), or nothing while it is hidden.
using Placement = std::function<std::optional<cv::Point2d>(const MarkerSpec&, int k)>;

DrawnRun track(const Placement& place, int frames, double scale = 2.4,
               const TrackerOptions& options = {}) {
  const MarkerLayout layout =
      load_layout(std::filesystem::path(ROSTRO_DATA_DIR) / "layouts" / "default.json");
  MarkerTracker tracker(layout, options);
  start_on_drawing(tracker, layout,
                   [&](const MarkerSpec& m) { return to_image(*place(m, 0), scale); });
  DrawnRun run;
  for (int k = 0; k < frames; ++k) {
    cv::Mat img(cvRound(480 * scale / 2.4), cvRound(640 * scale / 2.4), CV_8UC1, cv::Scalar(180));
    draw_and_track(
        tracker, layout, img, k, layout.dot_diameter_mm / 2 * scale,
        [&](const MarkerSpec& m) -> std::optional<cv::Point2d> {
          const auto mm = place(m, k);
          if (!mm) return std::nullopt;
          return to_image(*mm, scale);
        },
        run);
  }
  return run;
}

// The left eye's four dots drift toward the nose, 0.25 mm a frame from frame 5 to 40 (9 mm
// in all), while the rest of the face stays: the start positions' fit then puts the eye's
// dots mostly where they were. The lower lid and the outer corner are hidden in frames
// 41-44 and seen again from 45.
std::optional<cv::Point2d> drifting_eye(const MarkerSpec& m, int k) {
  cv::Point2d mm = m.frontal();
  if (!left_eye(m)) return mm;
  mm.x -= 0.25 * std::clamp(k - 5, 0, 36);
  if ((m.id == "lid_l_low" || m.id == "eye_l_out") && k >= 41 && k <= 44) return std::nullopt;
  return mm;
}

TEST(LidReacquire, LostLidFoundAgainWhereItWasLastSeen) {
  const DrawnRun run = track(drifting_eye, 52);
  for (int k = 47; k < 52; ++k) {
    const auto& seen = run.seen[static_cast<size_t>(k)];
    const auto& truth = run.truth[static_cast<size_t>(k)];
    ASSERT_TRUE(seen.count("lid_l_low")) << "frame " << k << ": the lower lid not found again";
    EXPECT_LT(cv::norm(seen.at("lid_l_low") - truth.at("lid_l_low")), 0.5) << "frame " << k;
  }
  // Never on another dot meanwhile.
  for (size_t k = 0; k < run.seen.size(); ++k) {
    for (const auto& [id, at] : run.seen[k]) {
      for (const auto& [other, where] : run.truth[k]) {
        if (other == id) continue;
        EXPECT_GT(cv::norm(at - where), 2.0) << id << " on " << other;
      }
    }
  }
}

// The pixel-valued options hold for 8-pixel dots and grow with the dots measured at the start:
// 20-px dots (5 px a millimetre), the face moving 2.5 px a frame, are followed as closely as
// small ones.
std::optional<cv::Point2d> sliding_face(const MarkerSpec& m, int k) {
  return m.frontal() + cv::Point2d(0.5 * k, 0);
}

TEST(PixelScale, LargeDotsFollowedAsSmallOnes) {
  constexpr double kScale = 5;
  const DrawnRun run = track(sliding_face, 20, kScale);
  for (size_t k = 1; k < run.seen.size(); ++k) {
    EXPECT_EQ(run.seen[k].size(), run.truth[k].size()) << "frame " << k << ": dots lost";
    for (const auto& [id, at] : run.seen[k]) {
      EXPECT_LT(cv::norm(at - run.truth[k].at(id)), 0.5) << "frame " << k << ": " << id;
    }
  }
}

}  // namespace
}  // namespace rostro::tracking
