// The head as dlib reads it (issue 24): a face on every render of the default head, and the
// check's own bad input.

#include "eval/head_check.hpp"

#include <gtest/gtest.h>

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
  }
  EXPECT_EQ(scored, 1);  // the neutral front view carries the landmark aim
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
