// Photo scenes (eval/photo_scene.hpp) on the real photographs of ../shared/fixtures/faces: the
// truth is where the markers are painted, and where the warp moves them.

#include "eval/photo_scene.hpp"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "facecore/error.hpp"
#include "tracking/dot_detector.hpp"
#include "tracking/landmark_model.hpp"

namespace rostro::eval {
namespace {

const std::filesystem::path kFaces = std::filesystem::path(ROSTRO_SHARED_DIR) / "fixtures/faces";

class PhotoScene : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(kFaces / "bald_guys.jpg"))
      GTEST_SKIP() << "no face photographs at " << kFaces << " (../shared/fixtures/faces)";
    if (!std::filesystem::exists(tracking::default_landmark_model()))
      GTEST_SKIP() << "no landmark model at " << tracking::default_landmark_model()
                   << " (Debian's libdlib-data)";
    layout = tracking::load_layout(tracking::default_layout_path());
    options.photo = kFaces / "bald_guys.jpg";
    options.face_px = 300;
    options.dot_px = 10;
    options.noise = 0;
    options.seconds = 0.4;
  }
  tracking::MarkerLayout layout;
  PhotoSceneOptions options;
};

TEST_F(PhotoScene, StillTruthIsThePaintedPositions) {
  options.motion = "still";
  long frames = 0;
  const PhotoSceneResult r = render_photo_scene(options, layout, [&](const cv::Mat& bgr) {
    EXPECT_EQ(bgr.size(), options.size);
    EXPECT_EQ(bgr.type(), CV_8UC3);
    ++frames;
  });
  ASSERT_EQ(frames, 10);
  ASSERT_EQ(r.truth.size(), 10u);
  ASSERT_EQ(r.painted.size(), layout.markers.size());
  for (const tracking::TrackedFrame& f : r.truth) {
    ASSERT_EQ(f.markers.size(), layout.markers.size());
    for (std::size_t i = 0; i < f.markers.size(); ++i) {
      EXPECT_EQ(f.markers[i].marker, layout.markers[i].id);
      EXPECT_TRUE(f.markers[i].valid) << f.markers[i].marker;
      EXPECT_EQ(f.markers[i].position, r.painted[i]) << f.markers[i].marker;
    }
  }
}

// The dot detector finds each plain-skin dot where the truth says, in a frame the warp has
// turned, squeezed and moved and the expression bumps have moved the mouth and brows: the
// truth is the forward warp of the painted centre, and the frame its exact inverse.
TEST_F(PhotoScene, WarpedDotIsWhereTheTruthSays) {
  options.motion = "talk";
  std::vector<cv::Mat> frames;
  const PhotoSceneResult r = render_photo_scene(
      options, layout, [&](const cv::Mat& bgr) { frames.push_back(bgr.clone()); });
  ASSERT_EQ(frames.size(), 10u);
  cv::Mat gray;
  cv::cvtColor(frames.back(), gray, cv::COLOR_BGR2GRAY);
  const tracking::TrackedFrame& truth = r.truth.back();
  int checked = 0;
  for (const char* id : {"cheek_r", "cheekbone_l", "cheekbone_r", "chin_boss"}) {
    const auto it = std::find_if(truth.markers.begin(), truth.markers.end(),
                                 [&](const auto& m) { return m.marker == id; });
    ASSERT_NE(it, truth.markers.end()) << id;
    // It moved: not where it was painted.
    const std::size_t i = static_cast<std::size_t>(it - truth.markers.begin());
    EXPECT_GT(cv::norm(it->position - r.painted[i]), 2.0) << id;
    const auto dot = tracking::refine_dot(gray, it->position, 6, tracking::DotOptions{});
    ASSERT_TRUE(dot.has_value()) << id;
    EXPECT_LT(cv::norm(dot->center - it->position), 0.1) << id;
    ++checked;
  }
  EXPECT_EQ(checked, 4);
}

TEST_F(PhotoScene, MissingPhotoIsAnInputErrorNamingIt) {
  options.photo = kFaces / "no_such_face.jpg";
  try {
    render_photo_scene(options, layout, [](const cv::Mat&) {});
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no_such_face.jpg"), std::string::npos) << e.what();
  }
}

TEST_F(PhotoScene, FaceIndexOutOfRangeIsAnInputError) {
  options.face = 999;
  EXPECT_THROW(render_photo_scene(options, layout, [](const cv::Mat&) {}), InputError);
}

}  // namespace
}  // namespace rostro::eval
