// The face prior on a real photograph of several faces: the landmarks come from the face the
// tags place the layout on and from no other, and the box the model's average face gives a
// face's own dots is the box the detector gave it.

#include "tracking/face_prior.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "tracking/landmark_model.hpp"
#include "tracking/layout.hpp"

namespace rostro::tracking {
namespace {

const std::filesystem::path kPhoto =
    std::filesystem::path(ROSTRO_SHARED_DIR) / "fixtures/faces/bald_guys.jpg";
constexpr int kNoseTip = 30;  // iBUG

MarkerLayout default_layout() {
  return load_layout(std::filesystem::path(ROSTRO_DATA_DIR) / "layouts" / "default.json");
}

// The layout's frontal millimetres to pixels with its origin (the nose tip) at `nose` and a
// face `face_px` wide: as three tags on the face's headband would give it.
cv::Matx23d layout_on(cv::Point2d nose, double face_px) {
  const double s = face_px / FacePrior::kFaceWidthMm;
  return {s, 0, nose.x, 0, s, nose.y};
}

struct Setup {
  cv::Mat gray;
  std::vector<FaceDetection> faces;
};

class FacePriorOnAPhoto : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(kPhoto)) GTEST_SKIP() << "../shared/fixtures/faces is absent";
    if (!std::filesystem::exists(default_landmark_model()))
      GTEST_SKIP() << "no " << default_landmark_model() << " (libdlib-data)";
    gray = cv::imread(kPhoto.string(), cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(gray.empty());
    faces = model.detect(gray, {0, 0, gray.cols, gray.rows}, 120, 0.0);
    ASSERT_GE(faces.size(), 2u) << "the photo's faces";
  }

  LandmarkModel model{default_landmark_model()};
  FacePrior prior{default_landmark_model()};
  MarkerLayout layout = default_layout();
  cv::Mat gray;
  std::vector<FaceDetection> faces;
};

TEST_F(FacePriorOnAPhoto, TheLandmarksAreOnTheFaceTheTagsPlace) {
  for (const FaceDetection& face : faces) {
    const cv::Point2d nose = model.fit(gray, face.box)[kNoseTip];
    const auto places = prior.expected(gray, layout, layout_on(nose, face.box.width));
    ASSERT_TRUE(places.count("nose_tip")) << "face at " << face.box;
    EXPECT_LT(cv::norm(places.at("nose_tip") - nose), 0.05 * face.box.width)
        << "face at " << face.box;
  }
}

TEST_F(FacePriorOnAPhoto, NoFaceWhereTheTagsPlaceNone) {
  // A point no detected face's box holds: the nearest face is another person, no evidence.
  cv::Point2d empty(-1, -1);
  for (int y = 0; y < gray.rows && empty.x < 0; y += 50)
    for (int x = 0; x < gray.cols && empty.x < 0; x += 50) {
      const cv::Point2d p(x, y);
      const bool free = std::none_of(faces.begin(), faces.end(), [&](const FaceDetection& f) {
        const cv::Rect2d grown(f.box.x - f.box.width, f.box.y - f.box.height, 3 * f.box.width,
                               3 * f.box.height);
        return grown.contains(p);
      });
      if (free) empty = p;
    }
  ASSERT_GE(empty.x, 0) << "a place in the photo away from every face";
  EXPECT_TRUE(prior.expected(gray, layout, layout_on(empty, faces[0].box.width)).empty());
}

TEST_F(FacePriorOnAPhoto, TheAverageFacesBoxIsTheDetectorsBox) {
  for (const FaceDetection& face : faces) {
    const auto places = prior.fitted(gray, layout, face.box);
    ASSERT_GE(places.size(), 10u);
    const auto box = prior.placed_box(layout, places);
    ASSERT_TRUE(box.has_value());
    // A face turned or tilted is not the average face: its box is placed within a sixth of its
    // width, close enough for the model's fit to start from.
    const double tolerance = 0.15 * face.box.width;
    EXPECT_NEAR(box->x, face.box.x, tolerance) << face.box;
    EXPECT_NEAR(box->y, face.box.y, tolerance) << face.box;
    EXPECT_NEAR(box->width, face.box.width, 2 * tolerance) << face.box;
  }
}

}  // namespace
}  // namespace rostro::tracking
