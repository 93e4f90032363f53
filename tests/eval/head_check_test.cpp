// The head as dlib reads it (issue 24): a face on every render of the default head, and the
// check's own bad input.

#include "eval/head_check.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "facecore/error.hpp"
#include "facecore/face_model.hpp"
#include "render/render_error.hpp"
#include "tracking/landmark_model.hpp"

namespace rostro::eval {
namespace {

struct Inputs {
  FaceModel model;
  ExpressionLibrary library;
};

// Skips (returns null) without the landmark model, the default head or OpenGL.
const Inputs* inputs(std::string& why) {
  static std::unique_ptr<Inputs> cached;
  static std::string reason;
  static bool tried = false;
  if (!tried) {
    tried = true;
    if (!std::filesystem::exists(tracking::default_landmark_model())) {
      reason = "no " + tracking::default_landmark_model().string() + " (libdlib-data)";
    } else {
      try {
        cached = std::make_unique<Inputs>(
            Inputs{load_default_face_model(), ExpressionLibrary::load_default()});
      } catch (const InputError& e) {
        reason = std::string("no default head: ") + e.what();
      }
    }
  }
  why = reason;
  return cached.get();
}

TEST(HeadCheck, DlibFindsTheDefaultHeadOnEveryRender) {
  std::string why;
  const Inputs* in = inputs(why);
  if (in == nullptr) GTEST_SKIP() << why;
  HeadCheckResult r;
  try {
    r = check_head(in->model, in->library);
  } catch (const render::RenderUnavailable& e) {
    GTEST_SKIP() << "no OpenGL: " << e.what();
  }
  std::printf("%s", head_check_table_text(r).c_str());
  ASSERT_EQ(r.renders, 21);  // three views, neutral and six expressions
  ASSERT_EQ(r.rows.size(), 21u);
  EXPECT_EQ(r.found, r.renders);
  int scored = 0;
  for (const HeadCheckRow& row : r.rows) {
    ASSERT_EQ(row.feature_error.size(), head_check_features().size());
    EXPECT_GT(row.iod_px, 100) << row.expression;  // the head fills the 640x480 view
    if (row.scored) ++scored;
    if (!row.found) continue;
    // A landmark set that is not this face at all would sit a whole IOD away.
    for (double e : row.feature_error) EXPECT_LT(e, 0.5) << row.expression << " " << row.yaw_deg;
    // The signed offsets are the same distances: each feature's largest is its error.
    std::size_t i = 0;
    for (std::size_t f = 0; f < head_check_features().size(); ++f) {
      double worst = 0;
      for (const FeaturePointId& p : head_check_features()[f].points) {
        ASSERT_LT(i, row.offsets.size());
        EXPECT_EQ(row.offsets[i].point, p);
        worst = std::max(worst, std::hypot(row.offsets[i].outward, row.offsets[i].up));
        ++i;
      }
      EXPECT_NEAR(worst, row.feature_error[f], 1e-9) << head_check_features()[f].name;
    }
    EXPECT_EQ(i, row.offsets.size());
  }
  EXPECT_EQ(scored, 1);  // the neutral front view carries the landmark aim
}

TEST(HeadCheck, OffsetsAreSignedAwayFromTheMidlineAndUp) {
  const FeaturePointId left_eye{3, 7}, right_eye{3, 12}, nose{9, 3};
  // The face's midline at x = 300, an IOD of 100 px; image y grows downward.
  const LandmarkOffset left = landmark_offset(left_eye, 345, 195, 350, 200, 300, 100);
  EXPECT_EQ(left.point, left_eye);
  EXPECT_NEAR(left.outward, -0.05, 1e-12);  // 5 px nearer the midline: inward
  EXPECT_NEAR(left.up, 0.05, 1e-12);        // 5 px higher in the image
  const LandmarkOffset right = landmark_offset(right_eye, 245, 210, 250, 200, 300, 100);
  EXPECT_NEAR(right.outward, 0.05, 1e-12);  // 5 px further from the midline: outward
  EXPECT_NEAR(right.up, -0.1, 1e-12);
  // A point on the midline takes the image's right as its outward side.
  const LandmarkOffset tip = landmark_offset(nose, 303, 250, 300.5, 250, 300, 100);
  EXPECT_NEAR(tip.outward, 0.025, 1e-12);
}

TEST(HeadCheck, MissingFeaturePointAndModelAreInputErrors) {
  std::string why;
  const Inputs* in = inputs(why);
  if (in == nullptr) GTEST_SKIP() << why;
  FaceModel without_chin = in->model;
  without_chin.feature_points.erase(FeaturePointId{2, 1});
  try {
    check_head(without_chin, in->library);
    FAIL() << "a head without 2.1 was checked";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("2.1"), std::string::npos) << e.what();
  }
  HeadCheckOptions options;
  options.landmark_model = "/nonexistent/shape_predictor.dat";
  try {
    check_head(in->model, in->library, options);
    FAIL() << "a missing landmark model was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/shape_predictor.dat"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace rostro::eval
