// Camera placement: parsing, automatic framing, and where the eye ends up.

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "facecore/error.hpp"
#include "render/camera.hpp"

namespace rostro::render {
namespace {

Bounds unit_box() {
  Bounds b;
  b.min = {-1.0f, -1.0f, -1.0f};
  b.max = {1.0f, 1.0f, 1.0f};
  return b;
}

// Projects a world point to normalised device coordinates.
Eigen::Vector3f project(const CameraMatrices& m, const Eigen::Vector3f& p) {
  const Eigen::Vector4f clip = m.projection * m.view * p.homogeneous();
  return clip.head<3>() / clip.w();
}

TEST(Camera, ParsesPresetsAndAngles) {
  EXPECT_EQ(parse_camera("front").yaw_deg, 0.0);
  EXPECT_GT(parse_camera("three-quarter").yaw_deg, 20.0);
  const CameraPose pose = parse_camera("10, -5,2.5");
  EXPECT_DOUBLE_EQ(pose.yaw_deg, 10.0);
  EXPECT_DOUBLE_EQ(pose.pitch_deg, -5.0);
  EXPECT_DOUBLE_EQ(pose.roll_deg, 2.5);
  const CameraPose far = parse_camera("0,0,0,300,40");
  EXPECT_DOUBLE_EQ(far.distance, 300.0);
  EXPECT_DOUBLE_EQ(far.fov_deg, 40.0);
  EXPECT_THROW(parse_camera("side"), InputError);
  EXPECT_THROW(parse_camera("1,2"), InputError);
  EXPECT_THROW(parse_camera("1,2,x"), InputError);
  EXPECT_THROW(parse_camera("0,0,0,10,200"), InputError);
}

TEST(Camera, FrontLooksDownMinusZAtTheCentre) {
  Bounds b = unit_box();
  b.min[2] += 4.0f;  // centre at z = 4
  b.max[2] += 4.0f;
  const CameraMatrices m = frame_camera(CameraPose::front(), b, 4.0 / 3.0);
  EXPECT_NEAR(m.eye.x(), 0.0f, 1e-4f);
  EXPECT_NEAR(m.eye.y(), 0.0f, 1e-4f);
  EXPECT_GT(m.eye.z(), 5.0f);
  const Eigen::Vector3f centre = project(m, Eigen::Vector3f(0, 0, 4));
  EXPECT_NEAR(centre.x(), 0.0f, 1e-5f);
  EXPECT_NEAR(centre.y(), 0.0f, 1e-5f);
  // The face's left (+x) appears on the image's right, up stays up.
  EXPECT_GT(project(m, Eigen::Vector3f(0.5f, 0, 4)).x(), 0.0f);
  EXPECT_GT(project(m, Eigen::Vector3f(0, 0.5f, 4)).y(), 0.0f);
}

TEST(Camera, AutomaticFramingKeepsEveryCornerInsideTheView) {
  for (const CameraPose& pose : {CameraPose::front(), CameraPose::three_quarter(),
                                 parse_camera("-60,30,10"), parse_camera("180,0,0")}) {
    for (const double aspect : {16.0 / 9.0, 1.0, 0.5}) {
      const CameraMatrices m = frame_camera(pose, unit_box(), aspect);
      double extent = 0.0;
      for (int c = 0; c < 8; ++c) {
        const Eigen::Vector3f corner((c & 1) ? 1.0f : -1.0f, (c & 2) ? 1.0f : -1.0f,
                                     (c & 4) ? 1.0f : -1.0f);
        const Eigen::Vector3f ndc = project(m, corner);
        EXPECT_LE(std::abs(ndc.x()), 1.0f) << describe(pose);
        EXPECT_LE(std::abs(ndc.y()), 1.0f) << describe(pose);
        EXPECT_GT(ndc.z(), -1.0f);
        EXPECT_LT(ndc.z(), 1.0f);
        extent = std::max({extent, double(std::abs(ndc.x())), double(std::abs(ndc.y()))});
      }
      // ... and tightly: the box reaches about 1 / margin of the view.
      EXPECT_NEAR(extent, 1.0 / pose.margin, 0.02) << describe(pose) << " aspect " << aspect;
    }
  }
}

TEST(Camera, YawMovesTheEyeTowardTheFacesLeft) {
  const CameraMatrices m = frame_camera(parse_camera("90,0,0"), unit_box(), 1.0);
  EXPECT_GT(m.eye.x(), 1.0f);
  EXPECT_NEAR(m.eye.z(), 0.0f, 1e-4f);
  const CameraMatrices up = frame_camera(parse_camera("0,45,0"), unit_box(), 1.0);
  EXPECT_GT(up.eye.y(), 1.0f);
}

TEST(Camera, GivenDistanceIsKept) {
  CameraPose pose;
  pose.distance = 12.5;
  const CameraMatrices m = frame_camera(pose, unit_box(), 1.0);
  EXPECT_NEAR(m.eye.z(), 12.5f, 1e-5f);
}

}  // namespace
}  // namespace rostro::render
