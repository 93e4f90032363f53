// The bare-face landmark tracker on faces it was not tuned on: the default head rendered bare
// (still with sensor noise, a fast jaw, the range of motion), and real photographs from
// ../shared/fixtures/faces moved by smooth warps, entering late and leaving.

#include "tracking/landmark_tracker.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "eval/synth.hpp"
#include "facecore/error.hpp"
#include "facecore/face_model.hpp"
#include "render/render_error.hpp"

namespace rostro::tracking {
namespace {

const std::filesystem::path kFaces = std::filesystem::path(ROSTRO_SHARED_DIR) / "fixtures/faces";

bool have_model() {
  return std::filesystem::exists(default_landmark_model());
}

// Root mean square over the landmarks of their motion from one frame to the next, averaged
// over the frames.
double mean_jitter(const std::vector<std::vector<cv::Point2d>>& frames) {
  double sum = 0;
  for (std::size_t f = 1; f < frames.size(); ++f) {
    double sq = 0;
    for (std::size_t i = 0; i < frames[f].size(); ++i) {
      const cv::Point2d d = frames[f][i] - frames[f - 1][i];
      sq += d.dot(d);
    }
    sum += std::sqrt(sq / static_cast<double>(frames[f].size()));
  }
  return sum / static_cast<double>(frames.size() - 1);
}

// The default head rendered bare, its truth at the feature points the landmarks name.
class BareHead : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!have_model()) GTEST_SKIP() << "no " << default_landmark_model() << " (libdlib-data)";
    try {
      model = load_default_face_model();
    } catch (const InputError& e) {
      GTEST_SKIP() << "no default head: " << e.what();
    }
    mapping = default_ibug_mapping();
    layout = landmark_layout(mapping, model.feature_point_positions());
  }
  // Renders `drive` bare; skips without OpenGL.
  std::vector<cv::Mat> render(const FapStream& drive, const eval::SynthOptions& o,
                              eval::SynthResult* truth = nullptr) {
    render::MemoryFrameSink sink;
    try {
      eval::SynthResult r =
          eval::synthesize(model, nullptr, eval::place_markers(model, layout), drive, o, sink);
      if (truth != nullptr) *truth = std::move(r);
    } catch (const render::RenderUnavailable& e) {
      return {};
    }
    return sink.frames;
  }
  FaceModel model;
  IbugMapping mapping;
  MarkerLayout layout;
};

FapStream neutral_stream(int frames, double fps) {
  FapStream s;
  s.header.fps = fps;
  for (int i = 0; i < frames; ++i) {
    FapFrame f;
    f.index = i;
    f.time_s = i / fps;
    s.frames.push_back(f);
  }
  s.header.frame_count = frames;
  return s;
}

TEST_F(BareHead, FindsTheHeadOnEveryFrameOfTheRangeOfMotion) {
  FapStream drive = eval::range_of_motion(25);
  drive.frames.resize(100);  // jaw, lip corners, lips
  eval::SynthResult truth;
  const auto frames = render(drive, {}, &truth);
  if (frames.empty()) GTEST_SKIP() << "no OpenGL";
  LandmarkTracker tracker(mapping, model.feature_point_positions());
  long valid = 0, total = 0;
  // The landmark scheme and the head's feature points name the same places only roughly (an
  // iBUG eye corner is where the eye's opening ends), so positions are compared as motion:
  // each observation's move since the first frame against its truth's.
  std::vector<TrackedFrame> tracked;
  for (std::size_t f = 0; f < frames.size(); ++f) {
    tracked.push_back(
        tracker.track(frames[f], static_cast<long>(f), static_cast<double>(f) / 25.0));
    ASSERT_EQ(tracked.back().markers.size(), layout.markers.size());
    for (const MarkerObservation& m : tracked.back().markers) valid += m.valid, ++total;
  }
  EXPECT_EQ(valid, total);
  EXPECT_EQ(tracker.searches(), 1);  // found once, then followed
  const auto& t0 = truth.truth[0].markers;
  std::size_t right = 0, left = 0;
  for (std::size_t k = 0; k < t0.size(); ++k) {
    if (t0[k].feature_point.str() == "3.12") right = k;
    if (t0[k].feature_point.str() == "3.7") left = k;
  }
  const double eyes = cv::norm(t0[left].position - t0[right].position);
  std::vector<double> errors;
  for (std::size_t f = 1; f < frames.size(); ++f)
    for (std::size_t k = 0; k < t0.size(); ++k) {
      const cv::Point2d moved = tracked[f].markers[k].position - tracked[0].markers[k].position;
      const cv::Point2d truly = truth.truth[f].markers[k].position - t0[k].position;
      errors.push_back(cv::norm(moved - truly) / eyes);
    }
  std::sort(errors.begin(), errors.end());
  std::printf("range of motion: landmark motion off by %.4f (median), %.4f (90th) eye distances\n",
              errors[errors.size() / 2], errors[errors.size() * 9 / 10]);
  EXPECT_LT(errors[errors.size() / 2], 0.02) << "eye distance " << eyes << " px";
  EXPECT_LT(errors[errors.size() * 9 / 10], 0.05);
}

TEST_F(BareHead, StillFaceJitterStaysUnderAThirdOfAPixel) {
  eval::SynthOptions o;
  o.noise_sigma = 2;
  o.seed = 5;
  const auto frames = render(neutral_stream(50, 25), o);
  if (frames.empty()) GTEST_SKIP() << "no OpenGL";
  // The reported observations (the mapped landmarks), as the fit receives them.
  const auto run = [&](bool stabilise) {
    LandmarkTrackerOptions options;
    options.stabilise = stabilise;
    LandmarkTracker tracker(mapping, model.feature_point_positions(), options);
    std::vector<std::vector<cv::Point2d>> reported;
    for (std::size_t f = 0; f < frames.size(); ++f) {
      const TrackedFrame t =
          tracker.track(frames[f], static_cast<long>(f), static_cast<double>(f) / 25.0);
      if (f < 10) continue;  // the stabiliser settles
      reported.emplace_back();
      for (const MarkerObservation& m : t.markers) reported.back().push_back(m.position);
    }
    return mean_jitter(reported);
  };
  const double stabilised = run(true), raw = run(false);
  std::printf("still face, noise 2: jitter %.3f px stabilised, %.3f px raw\n", stabilised, raw);
  EXPECT_LE(stabilised, 0.3) << "raw " << raw;
  EXPECT_LT(stabilised, raw / 3);  // the stabiliser does the work
}

TEST_F(BareHead, FastJawOpeningLagsAtMostOneFrame) {
  // The jaw opens fully within three frames, after a still second.
  FapStream drive = neutral_stream(50, 25);
  for (std::size_t f = 25; f < drive.frames.size(); ++f)
    drive.frames[f].set(3, std::min(1.0, (static_cast<double>(f) - 24) / 3) * 600);
  eval::SynthOptions o;
  o.noise_sigma = 2;
  const auto frames = render(drive, o);
  if (frames.empty()) GTEST_SKIP() << "no OpenGL";
  constexpr std::size_t kChin = 8;  // iBUG 9
  std::vector<double> raw_y, filtered_y;
  LandmarkTracker tracker(mapping, model.feature_point_positions());
  for (std::size_t f = 0; f < frames.size(); ++f) {
    tracker.track(frames[f], static_cast<long>(f), static_cast<double>(f) / 25.0);
    raw_y.push_back(tracker.raw_landmarks()[kChin].y);
    filtered_y.push_back(tracker.landmarks()[kChin].y);
  }
  const double before = raw_y[20], after = raw_y.back();
  ASSERT_GT(after - before, 10) << "the chin should drop";
  // The frame each curve first passes half the step.
  const auto half_way = [&](const std::vector<double>& y) {
    for (std::size_t f = 21; f < y.size(); ++f)
      if (y[f] - before > (after - before) / 2) return static_cast<long>(f);
    return -1L;
  };
  std::printf("fast jaw: the stabilised chin passes half way %ld frame(s) after the raw fit\n",
              half_way(filtered_y) - half_way(raw_y));
  EXPECT_LE(half_way(filtered_y) - half_way(raw_y), 1);
  // And it settles where the fit is: over the last ten frames, once the jaw has stopped, the
  // two agree within half a pixel on average (one raw frame alone jitters by more).
  double filtered_mean = 0, raw_mean = 0;
  for (std::size_t f = 40; f < 50; ++f)
    filtered_mean += filtered_y[f] / 10, raw_mean += raw_y[f] / 10;
  EXPECT_NEAR(filtered_mean, raw_mean, 0.5);
}

// A real photograph moved by a smooth warp (a sub-pixel translation and slight zoom),
// entering after blank frames and leaving before the end.
class RealFace : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!have_model()) GTEST_SKIP() << "no " << default_landmark_model() << " (libdlib-data)";
    photo = cv::imread((kFaces / "2008_001322.jpg").string());
    if (photo.empty()) GTEST_SKIP() << "../shared/fixtures/faces is absent";
    cv::resize(photo, photo, {}, 2.0, 2.0, cv::INTER_CUBIC);  // faces about 100 px wide
    neutral[*parse_feature_point("9.3")] = Eigen::Vector3d::Zero();
    for (const IbugMarker& m : default_ibug_mapping().markers)
      neutral.try_emplace(m.feature_point, Eigen::Vector3d::Zero());
  }
  // Frame `f` of the clip: the photo shifted by `shift(f)` and scaled about its centre.
  cv::Mat frame(const cv::Point2d& shift, double scale) const {
    const cv::Point2d c(photo.cols / 2.0, photo.rows / 2.0);
    cv::Mat m = cv::getRotationMatrix2D(c, 0, scale);
    m.at<double>(0, 2) += shift.x;
    m.at<double>(1, 2) += shift.y;
    cv::Mat out;
    cv::warpAffine(photo, out, m, photo.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT);
    return out;
  }
  cv::Mat photo;
  FeaturePointPositions neutral;
};

TEST_F(RealFace, FollowsASmoothWarpLateStartAndExit) {
  LandmarkTrackerOptions o;
  o.min_face_px = 60;
  LandmarkTracker tracker(default_ibug_mapping(), neutral, o);
  const cv::Mat blank(photo.size(), photo.type(), cv::Scalar(128, 128, 128));
  // Blank frames: nothing found, every observation invalid.
  for (int f = 0; f < 5; ++f) {
    const TrackedFrame t = tracker.track(blank, f, static_cast<double>(f) / 25.0);
    for (const MarkerObservation& m : t.markers) EXPECT_FALSE(m.valid);
  }
  EXPECT_FALSE(tracker.started());
  // The face enters and drifts 30 px right and 10 px down while growing 6 %.
  std::vector<cv::Point2d> first;
  std::vector<double> errors;
  cv::Point2d first_centre;
  for (int f = 0; f < 30; ++f) {
    const double s = f / 29.0;
    const cv::Point2d shift(30 * s, 10 * s);
    const double scale = 1.0 + 0.06 * s;
    const TrackedFrame t = tracker.track(frame(shift, scale), 5 + f, (5 + f) / 25.0);
    ASSERT_TRUE(tracker.started());
    const auto& lm = tracker.landmarks();
    ASSERT_EQ(lm.size(), 68u);
    for (const MarkerObservation& m : t.markers) EXPECT_TRUE(m.valid) << m.marker;
    if (f == 0) {
      first = lm;
      continue;
    }
    // Where the warp took each landmark of the first frame.
    const cv::Point2d c(photo.cols / 2.0, photo.rows / 2.0);
    for (std::size_t i = 0; i < lm.size(); ++i) {
      const cv::Point2d expected = c + (first[i] - c) * (scale / 1.0) + shift;
      errors.push_back(cv::norm(lm[i] - expected));
    }
  }
  std::sort(errors.begin(), errors.end());
  // dlib's model on a 300-W face scores about 0.05 of the eye distance; a face lost or drifting
  // is past 0.1.
  const double eyes = cv::norm(first[36] - first[45]);
  std::printf("real photo warped: median %.2f px off the warp, %.3f of the eye distance\n",
              errors[errors.size() / 2], errors[errors.size() / 2] / eyes);
  EXPECT_LT(errors[errors.size() / 2] / eyes, 0.06)
      << errors[errors.size() / 2] << " px of " << eyes;
  // The face leaves: the frame it is gone is invalid.
  const TrackedFrame gone = tracker.track(blank, 40, 40 / 25.0);
  for (const MarkerObservation& m : gone.markers) EXPECT_FALSE(m.valid) << m.marker;
}

TEST(LandmarkTrackerOptions, RejectsNonsense) {
  LandmarkTrackerOptions o;
  o.face_rank = 0;
  EXPECT_THROW(o.validate(), InputError);
  o = {};
  o.box_deadband = 1.5;
  EXPECT_THROW(o.validate(), InputError);
  o = {};
  o.stabiliser.follow_share = 0;
  EXPECT_THROW(o.validate(), InputError);
  o = {};
  o.look_window = 0.5;  // a window smaller than the face cannot hold it
  EXPECT_THROW(o.validate(), InputError);
  EXPECT_NO_THROW(LandmarkTrackerOptions{}.validate());
}

}  // namespace
}  // namespace rostro::tracking
