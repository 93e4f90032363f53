#pragma once
// Does a face detector trained on real photographs read a head as a face, with its features
// where the head has them (issue 24)? The head is rendered neutral and with each of the six
// expressions, from the front and turned, and dlib's HOG face detector and 68-point model
// (tracking::LandmarkModel, trained on photographs) are run on each render. A face must be
// found on every render; on the neutral front view each feature's landmarks must lie near the
// head's own feature points projected by the renderer's camera, in shares of the inter-ocular
// distance (the projected outer eye corners 3.12 and 3.7, as 300-W normalises).
//
// Landmarks are named by feature point through data/eval/ibug68_to_mpeg4.json. The chin (2.1)
// is iBUG 9, the jaw's silhouette at the bottom: the two coincide seen from the front only.

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "facecore/expression_library.hpp"
#include "facecore/face_model.hpp"
#include "facecore/feature_point.hpp"

namespace rostro::eval {

struct HeadCheckOptions {
  int width = 640, height = 480;
  std::vector<double> yaws_deg{0, -30, 30};  // camera yaw of each view (render::CameraPose)
  int expression_intensity = 63;             // of 63
  std::filesystem::path landmark_model;      // empty: tracking::default_landmark_model()
  double min_face_px = 100;                  // smallest face the detector looks for
  double aim_share = 0.03;                   // each checked landmark within this share of the IOD
  // When set, each render is written here as <view>_<expression>.png with dlib's 68
  // landmarks (green), the head's checked feature points (red) and the face box (blue).
  std::filesystem::path image_dir;
};

// A feature the check scores and the feature points it is made of.
struct HeadFeature {
  std::string name;  // "eye corners", "mouth corners", "nose tip", "chin", "brows"
  std::vector<FeaturePointId> points;
};
const std::vector<HeadFeature>& head_check_features();

// Where dlib's landmark lies from the head's own point, signed, in shares of the IOD: `outward`
// away from the face's midline (for a point on it, the nose tip and the chin, toward the image's
// right), `up` toward the top of the image. A reading all inward (eye and mouth corners pulled
// toward the middle) says something else than one scattered about: it says which way the head
// differs from the faces the model was trained on.
struct LandmarkOffset {
  FeaturePointId point;
  double outward = 0, up = 0;
};
// The offset of a landmark at (landmark_x, landmark_y) from the head's point at (point_x,
// point_y), image pixels (y down), for a face whose midline is the image column midline_x.
LandmarkOffset landmark_offset(const FeaturePointId& point, double landmark_x, double landmark_y,
                               double point_x, double point_y, double midline_x, double iod_px);

struct HeadCheckRow {
  std::string expression;  // "neutral", "joy", ...
  double yaw_deg = 0;
  bool found = false;
  double confidence = 0;  // the detector's score (0 at its threshold)
  double iod_px = 0;      // projected 3.12 to 3.7
  // Per head_check_features() entry: the largest error among its points, share of iod_px
  // (NaN when no face was found).
  std::vector<double> feature_error;
  // Per checked point, in head_check_features() order (empty when no face was found).
  std::vector<LandmarkOffset> offsets;
  std::string worst_point;  // the point with the largest error ("3.7")
  double worst_error = 0;   // share of iod_px
  bool scored = false;      // the aim applies to this row (neutral, front)
};

struct HeadCheckResult {
  HeadCheckOptions options;
  std::vector<HeadCheckRow> rows;  // per view, neutral then the six expressions
  int renders = 0, found = 0;
  bool landmarks_met = false;  // every feature of the scored rows within aim_share
};

// Renders check_head() makes with these options: each view, neutral and the six expressions.
long head_check_renders(const HeadCheckOptions& options);

// Throws render::RenderUnavailable without OpenGL, InputError for a missing landmark model or
// a model without the checked feature points. `progress` gets renders done and the total.
HeadCheckResult check_head(const FaceModel& model, const ExpressionLibrary& library,
                           const HeadCheckOptions& options = {},
                           const std::function<void(long, long)>& progress = {});

// A row per render, then the neutral front view's signed offsets, a row per checked point.
std::string head_check_table_text(const HeadCheckResult& result);
std::string head_check_table_markdown(const HeadCheckResult& result);

}  // namespace rostro::eval
