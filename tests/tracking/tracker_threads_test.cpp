// The tracker on two threads (TrackerOptions::threads, `rostro capture` on two cores) gives
// the same tracks as on one, bit for bit: a drawn colour take with occlusions (markers lost and
// found again) tracked by both, every position, validity and quality compared exactly.

#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

#include "tests/support/synthetic_scene.hpp"
#include "tracking/layout.hpp"
#include "tracking/marker_tracker.hpp"

namespace fs = std::filesystem;
using namespace rostro::tracking;
using rostro::tracking::testing::SceneOptions;
using rostro::tracking::testing::SyntheticScene;
using rostro::tracking::testing::Truth;

namespace {

// OpenCV's pool capped at two threads for the test, whatever the machine.
class OpenCvThreads {
 public:
  explicit OpenCvThreads(int n) : was_(cv::getNumThreads()) { cv::setNumThreads(n); }
  ~OpenCvThreads() { cv::setNumThreads(was_); }

 private:
  int was_;
};

TEST(TrackerThreads, TwoThreadsTrackExactlyAsOne) {
  const OpenCvThreads pool(2);
  const MarkerLayout layout = load_layout(fs::path(ROSTRO_DATA_DIR) / "layouts" / "default.json");
  SceneOptions o;
  o.noise_sigma = 3;
  o.expression_px = 4;
  // A hand over the mouth, then one over the left brow and eye.
  o.occluders = {{{330, 300, 90, 60}, 8, 14}, {{340, 180, 70, 60}, 20, 24}};
  const SyntheticScene scene(layout, o);
  TrackerOptions one, two;
  one.threads = 1;
  two.threads = 2;
  one.identification.face_model.clear();  // a skin texture, not a face
  two.identification.face_model.clear();
  MarkerTracker serial(layout, one), parallel(layout, two);
  long valid = 0, lost = 0;
  for (int k = 0; k < 32; ++k) {
    std::map<std::string, Truth> truth;
    cv::Mat colour;
    // Colour input: the tracker converts to grey only the windows it reads, which the
    // threads then share.
    cv::cvtColor(scene.render(k, truth), colour, cv::COLOR_GRAY2BGR);
    const TrackedFrame a = serial.track(colour, k, k / 30.0);
    const TrackedFrame b = parallel.track(colour, k, k / 30.0);
    ASSERT_EQ(a.markers.size(), b.markers.size());
    for (std::size_t i = 0; i < a.markers.size(); ++i) {
      const MarkerObservation &x = a.markers[i], &y = b.markers[i];
      ASSERT_EQ(x.valid, y.valid) << "frame " << k << " " << x.marker;
      if (x.valid) {
        // Exact: the same arithmetic on the same pixels, whichever thread did it.
        EXPECT_EQ(x.position.x, y.position.x) << "frame " << k << " " << x.marker;
        EXPECT_EQ(x.position.y, y.position.y) << "frame " << k << " " << x.marker;
      }
      EXPECT_EQ(x.quality, y.quality) << "frame " << k << " " << x.marker;
      x.valid ? ++valid : ++lost;
    }
  }
  // The take is tracked, and the occluders make markers lost and found again.
  EXPECT_GT(valid, 32 * 25);
  EXPECT_GT(lost, 0);
}

}  // namespace
