// The default head rendered offscreen: it is where the camera puts it, and FAPs change the
// pixels they should (the jaw opens a dark mouth, a brow FAP leaves the mouth alone).

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "face_test_support.hpp"
#include "render/fap_assignments.hpp"

namespace rostro::render {
namespace {

using testing::covered_fraction;
using testing::DefaultHead;
using testing::project;

constexpr int kWidth = 320;
constexpr int kHeight = 240;

Eigen::Vector3d point(const char* id) {
  return DefaultHead::get().model.feature_point(*parse_feature_point(id));
}

double mean_luminance(const cv::Mat& bgr, const cv::Rect& box) {
  cv::Mat gray;
  cv::cvtColor(bgr(box), gray, cv::COLOR_BGR2GRAY);
  return cv::mean(gray)[0];
}

TEST(FaceRender, HeadFillsTheMiddleOfTheFrontView) {
  MAKE_FACE_RENDERER_OR_SKIP(face, kWidth, kHeight);
  const cv::Mat image = face->render(FapFrame{}, CameraPose::front());
  ASSERT_EQ(image.size(), cv::Size(kWidth, kHeight));
  const double covered = covered_fraction(image, cv::Rect(0, 0, kWidth, kHeight));
  EXPECT_GT(covered, 0.20);
  EXPECT_LT(covered, 0.85);
  for (const cv::Rect corner : {cv::Rect(0, 0, 12, 12), cv::Rect(kWidth - 12, 0, 12, 12),
                                cv::Rect(0, kHeight - 12, 12, 12)}) {
    EXPECT_LT(covered_fraction(image, corner), 0.05);
  }
  // The nose tip and both pupils land on the head, inside the image, left eye on the right.
  const auto nose = project(*face, CameraPose::front(), kWidth, kHeight, point("9.3"));
  const auto left_eye = project(*face, CameraPose::front(), kWidth, kHeight, point("3.5"));
  const auto right_eye = project(*face, CameraPose::front(), kWidth, kHeight, point("3.6"));
  EXPECT_NEAR(nose.x, kWidth / 2.0, kWidth * 0.1);
  EXPECT_GT(left_eye.x, right_eye.x);
  EXPECT_LT(left_eye.y, nose.y);
  for (const auto& p : {nose, left_eye, right_eye}) {
    ASSERT_TRUE(cv::Rect(0, 0, kWidth, kHeight).contains(p));
    EXPECT_GT(covered_fraction(image, cv::Rect(cv::Point(p) - cv::Point(2, 2), cv::Size(5, 5))),
              0.99);
  }
}

TEST(FaceRender, OpenJawDarkensTheMouth) {
  MAKE_FACE_RENDERER_OR_SKIP(face, kWidth, kHeight);
  const CameraPose pose = CameraPose::front();
  const cv::Mat neutral = face->render(FapFrame{}, pose);
  const cv::Mat open = face->render(parse_fap_assignments("open_jaw=600"), pose);
  // Between the inner lip midpoints (2.2 above, 2.3 below) and a third of the mouth wide.
  const auto upper = project(*face, pose, kWidth, kHeight, point("2.2"));
  const auto lower = project(*face, pose, kWidth, kHeight, point("2.3"));
  const auto corner_l = project(*face, pose, kWidth, kHeight, point("8.3"));
  const auto corner_r = project(*face, pose, kWidth, kHeight, point("8.4"));
  const int half_width = std::max(2, static_cast<int>(std::abs(corner_l.x - corner_r.x) / 6));
  const int top = static_cast<int>(std::min(upper.y, lower.y)) + 1;
  const cv::Rect mouth(static_cast<int>(upper.x) - half_width, top, 2 * half_width,
                       std::max(3, static_cast<int>(std::abs(lower.y - upper.y)) + 6));
  const double before = mean_luminance(neutral, mouth);
  const double after = mean_luminance(open, mouth);
  EXPECT_LT(after, 0.7 * before) << "mouth box " << mouth << ": " << before << " -> " << after;
  // The forehead does not change.
  const auto brow = project(*face, pose, kWidth, kHeight, point("4.1"));
  const cv::Rect forehead(static_cast<int>(brow.x) - 10, static_cast<int>(brow.y) - 30, 20, 15);
  EXPECT_NEAR(mean_luminance(open, forehead), mean_luminance(neutral, forehead), 1.0);
}

TEST(FaceRender, BrowFapChangesPixelsAboveTheEyesOnly) {
  MAKE_FACE_RENDERER_OR_SKIP(face, kWidth, kHeight);
  const CameraPose pose = CameraPose::front();
  const cv::Mat neutral = face->render(FapFrame{}, pose);
  const cv::Mat raised =
      face->render(parse_fap_assignments("raise_l_i_eyebrow=300,raise_l_m_eyebrow=300"), pose);
  cv::Mat diff;
  cv::absdiff(neutral, raised, diff);
  cv::cvtColor(diff, diff, cv::COLOR_BGR2GRAY);
  const auto nose = project(*face, pose, kWidth, kHeight, point("9.3"));
  const int split = static_cast<int>(nose.y);
  const int changed_above = cv::countNonZero(diff(cv::Rect(0, 0, kWidth, split)) > 8);
  const int changed_below = cv::countNonZero(diff(cv::Rect(0, split, kWidth, kHeight - split)) > 8);
  EXPECT_GT(changed_above, 20);
  EXPECT_EQ(changed_below, 0);
  // The left brow is on the image's right: more change right of the nose than left of it.
  const int x = static_cast<int>(nose.x);
  const int right_half = cv::countNonZero(diff(cv::Rect(x, 0, kWidth - x, split)) > 8);
  EXPECT_GT(right_half, changed_above / 2);
}

TEST(FaceRender, ExpressionsThroughFap2ChangeTheFace) {
  MAKE_FACE_RENDERER_OR_SKIP(face, kWidth, kHeight);
  const cv::Mat neutral = face->render(FapFrame{}, CameraPose::front());
  for (int select = 1; select <= 6; ++select) {
    FapFrame frame;
    ExpressionParams e;
    e.select1 = select;
    e.intensity1 = 63;
    frame.set_expression(e);
    cv::Mat diff;
    cv::absdiff(neutral, face->render(frame, CameraPose::front()), diff);
    cv::cvtColor(diff, diff, cv::COLOR_BGR2GRAY);
    EXPECT_GT(cv::countNonZero(diff > 8), 100) << ExpressionLibrary::expression_name(select);
  }
}

TEST(FaceRender, ThreeQuarterViewStillFramesTheHead) {
  MAKE_FACE_RENDERER_OR_SKIP(face, kWidth, kHeight);
  const cv::Mat image = face->render(FapFrame{}, CameraPose::three_quarter());
  EXPECT_GT(covered_fraction(image, cv::Rect(0, 0, kWidth, kHeight)), 0.2);
  EXPECT_LT(covered_fraction(image, cv::Rect(0, 0, kWidth, 2)), 0.05);
  // The face from brows to chin is inside the image, the chin above its bottom tenth (the neck
  // and shoulders go on below it).
  for (const char* id : {"4.5", "4.6", "9.3", "2.1", "3.5", "3.6"}) {
    const auto p = project(*face, CameraPose::three_quarter(), kWidth, kHeight, point(id));
    EXPECT_TRUE(cv::Rect(0, 0, kWidth, kHeight * 9 / 10).contains(p)) << id << " at " << p;
  }
}

TEST(FaceRender, PortraitFramingIsTheHeadNotTheShoulders) {
  // The default head goes on into shoulders 400 mm wide; the portrait box is the head's from a
  // little below the chin to the top of the skull (11.4, under the hair), as wide as the head
  // with its ears.
  const FaceModel& model = DefaultHead::get().model;
  Bounds full;
  full.min = full.max = {model.positions[0].x(), model.positions[0].y(), model.positions[0].z()};
  for (const Eigen::Vector3f& p : model.positions)
    for (std::size_t k = 0; k < 3; ++k) {
      full.min[k] = std::min(full.min[k], p[static_cast<Eigen::Index>(k)]);
      full.max[k] = std::max(full.max[k], p[static_cast<Eigen::Index>(k)]);
    }
  ASSERT_GT(full.size()[0], 350.0f) << "the default head has no shoulders";
  const Bounds portrait = portrait_bounds(model, full);
  const double chin = point("2.1").y(), ear = point("10.3").x();  // the left ear's back
  EXPECT_LT(portrait.min[1], chin);
  EXPECT_GT(portrait.min[1], chin - 40);
  EXPECT_EQ(portrait.max[1], static_cast<float>(point("11.4").y()));
  EXPECT_LT(portrait.max[1], full.max[1]) << "the hair stands above the skull";
  EXPECT_GT(portrait.max[0], ear);
  EXPECT_LT(portrait.max[0], 110.0f);
  EXPECT_LT(portrait.size()[2], 250.0f);
}

}  // namespace
}  // namespace rostro::render
