#include "eval/synth.hpp"

#include <gtest/gtest.h>

#include "facecore/error.hpp"
#include "render/render_error.hpp"
#include "tracking/apriltag_detector.hpp"

namespace rostro::eval {
namespace {

// Keeps the frames in memory: the test looks at the pixels under the truth.
class MemorySink : public render::FrameSink {
 public:
  void write(const cv::Mat& bgr) override { frames.push_back(bgr.clone()); }
  void finish() override { finished = true; }
  long frames_written() const override { return static_cast<long>(frames.size()); }
  std::vector<cv::Mat> frames;
  bool finished = false;
};

// The default head wearing the default layout's markers; skips without the head.
class SynthScene : public ::testing::Test {
 protected:
  void SetUp() override {
    try {
      model = load_default_face_model();
    } catch (const InputError& e) {
      GTEST_SKIP() << "no default head: " << e.what();
    }
    layout = tracking::load_layout(tracking::default_layout_path());
    markers = place_markers(model, layout);
  }
  // A small 320x240 clip of the layout's dots.
  SynthOptions small_clip() const {
    SynthOptions o;
    o.width = 320;
    o.height = 240;
    o.dot_diameter_mm = layout.dot_diameter_mm;
    return o;
  }
  FaceModel model;
  tracking::MarkerLayout layout;
  std::vector<PaintedMarker> markers;  // point into `layout`
};

TEST(Synth, RangeOfMotionMovesTheJawFirst) {
  const FapStream s = range_of_motion(25);
  EXPECT_EQ(s.frames.size(), 200u);
  EXPECT_NEAR(s.frames[12].get(3), 350, 2);  // the middle of the first second
  EXPECT_EQ(s.frames[0].get(3), 0);
  EXPECT_EQ(s.frames[37].get(3), 0);
}

TEST_F(SynthScene, TruthSitsOnTheDrawnDots) {
  ASSERT_GE(markers.size(), 20u);
  FapStream drive = range_of_motion(25);
  drive.frames.resize(4);
  const SynthOptions o = small_clip();
  MemorySink sink;
  SynthResult r;
  try {
    r = synthesize(model, nullptr, markers, drive, o, sink);
  } catch (const render::RenderUnavailable& e) {
    GTEST_SKIP() << "no OpenGL: " << e.what();
  }
  ASSERT_TRUE(sink.finished);
  ASSERT_EQ(sink.frames.size(), 4u);
  ASSERT_EQ(r.truth.size(), 4u);
  EXPECT_NEAR(r.intrinsics.cx, 159.5, 1e-9);
  EXPECT_GT(r.intrinsics.fx, 100.0);

  int visible = 0, dark = 0;
  cv::Point2d left_eye, right_eye;
  for (const auto& m : r.truth[3].markers) {
    if (m.feature_point.str() == "3.7") left_eye = m.position;
    if (m.feature_point.str() == "3.12") right_eye = m.position;
    if (!m.valid || layout.find(m.marker)->is_tag()) continue;
    ++visible;
    const cv::Vec3b px = sink.frames[3].at<cv::Vec3b>(cvRound(m.position.y), cvRound(m.position.x));
    if (px[0] + px[1] + px[2] < 3 * 80) ++dark;
  }
  EXPECT_GE(visible, 20);
  EXPECT_EQ(dark, visible);  // every visible truth point lands on a dark dot
  // The face's left eye is on the viewer's right in an unmirrored frontal view.
  EXPECT_GT(left_eye.x, right_eye.x + 20);
}

TEST_F(SynthScene, ACameraHeldAboveSeesTheFaceFromAbove) {
  FapStream drive = range_of_motion(25);
  drive.frames.resize(1);
  SynthOptions o = small_clip();
  o.elevation_deg = 75;
  MemorySink sink;
  try {
    EXPECT_THROW(synthesize(model, nullptr, markers, drive, o, sink), InputError);
    // Seen from 20 degrees above, the brows' dots come nearer the mouth's in the image than
    // seen level (the forehead leans back from the line of sight, the face is foreshortened).
    auto brow_to_mouth = [&](double elevation) {
      o.elevation_deg = elevation;
      MemorySink frames;
      const SynthResult r = synthesize(model, nullptr, markers, drive, o, frames);
      double brow = 0, mouth = 0;
      for (const auto& m : r.truth[0].markers) {
        if (m.feature_point.str() == "4.3") brow = m.position.y;
        if (m.feature_point.str() == "8.1") mouth = m.position.y;
      }
      return mouth - brow;
    };
    const double level = brow_to_mouth(0), above = brow_to_mouth(20);
    EXPECT_GT(level, 20.0);
    EXPECT_LT(above, level * 0.99);
  } catch (const render::RenderUnavailable& e) {
    GTEST_SKIP() << "no OpenGL: " << e.what();
  }
}

TEST_F(SynthScene, TagDetectorFindsTheDrawnTagsAtTheirTruth) {
  int tags = 0;
  for (const auto& m : markers) tags += m.spec->is_tag();
  ASSERT_EQ(tags, layout.tag_count());
  FapStream drive = range_of_motion(25);
  drive.frames.resize(3);
  SynthOptions o;
  o.yaw_deg = 20;  // a turned head: the tags move and foreshorten with it
  o.motion_period_s = 0.5;
  MemorySink sink;
  SynthResult r;
  try {
    r = synthesize(model, nullptr, markers, drive, o, sink);
  } catch (const render::RenderUnavailable& e) {
    GTEST_SKIP() << "no OpenGL: " << e.what();
  }
  tracking::AprilTagOptions full_resolution;
  full_resolution.decimation = 1;  // the turned tags are small: about 3 px per bit cell
  tracking::AprilTagDetector detector(full_resolution);
  for (std::size_t f = 0; f < sink.frames.size(); ++f) {
    const auto found = detector.detect(sink.frames[f]);
    int checked = 0;
    for (const auto& truth : r.truth[f].markers) {
      if (!layout.find(truth.marker)->is_tag() || !truth.valid) continue;
      auto it = std::find_if(found.begin(), found.end(), [&](const tracking::TagDetection& d) {
        return d.marker_id() == truth.marker;
      });
      ASSERT_NE(it, found.end()) << "frame " << f << ": " << truth.marker << " not found";
      EXPECT_LT(cv::norm(it->center - truth.position), 1.0) << truth.marker << " frame " << f;
      ++checked;
    }
    EXPECT_GE(checked, 2) << "frame " << f;
  }
}

}  // namespace
}  // namespace rostro::eval
