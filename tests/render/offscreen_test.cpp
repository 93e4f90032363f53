// The offscreen renderer draws headless, where the camera says, and the image follows the
// mesh. Skips (with the reason) when this machine has no EGL/OpenGL 3.3.

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>

#include "render/offscreen_renderer.hpp"
#include "render/render_error.hpp"
#include "test_shapes.hpp"

namespace rostro::render {
namespace {

std::unique_ptr<OffscreenRenderer> make_renderer(RenderOptions options, std::string& why) {
  try {
    return std::make_unique<OffscreenRenderer>(options);
  } catch (const RenderUnavailable& e) {
    why = e.what();
    return nullptr;
  }
}

#define MAKE_RENDERER_OR_SKIP(var, options)           \
  std::string why_unavailable;                        \
  auto var = make_renderer(options, why_unavailable); \
  if (!var) GTEST_SKIP() << "no headless OpenGL (EGL) here: " << why_unavailable

bool is_background(const cv::Vec3b& pixel, const Shading& shading) {
  for (int c = 0; c < 3; ++c) {
    const double expected = shading.background[static_cast<std::size_t>(2 - c)] * 255.0;
    if (std::abs(pixel[c] - expected) > 2.0) return false;
  }
  return true;
}

double covered_fraction(const cv::Mat& image, const cv::Rect& area, const Shading& shading) {
  int covered = 0;
  for (int y = area.y; y < area.y + area.height; ++y) {
    for (int x = area.x; x < area.x + area.width; ++x) {
      if (!is_background(image.at<cv::Vec3b>(y, x), shading)) ++covered;
    }
  }
  return static_cast<double>(covered) / area.area();
}

TEST(OffscreenRenderer, DrawsTheMeshInTheMiddleOfTheImage) {
  RenderOptions options;
  options.width = 320;
  options.height = 240;
  MAKE_RENDERER_OR_SKIP(renderer, options);
  renderer->set_mesh(testing::make_ellipsoid(1.0f, 1.3f, 1.0f));
  const cv::Mat image = renderer->render(CameraPose::front());
  ASSERT_EQ(image.type(), CV_8UC3);
  ASSERT_EQ(image.cols, 320);
  ASSERT_EQ(image.rows, 240);
  // The centre is all mesh, the left and right margins all background.
  EXPECT_GT(covered_fraction(image, cv::Rect(140, 100, 40, 40), options.shading), 0.99);
  EXPECT_LT(covered_fraction(image, cv::Rect(0, 0, 40, 240), options.shading), 0.01);
  EXPECT_LT(covered_fraction(image, cv::Rect(280, 0, 40, 240), options.shading), 0.01);
  // Automatic framing: the mesh spans most of the height without touching the edges.
  EXPECT_GT(covered_fraction(image, cv::Rect(159, 30, 2, 180), options.shading), 0.99);
  EXPECT_LT(covered_fraction(image, cv::Rect(0, 0, 320, 3), options.shading), 0.01);
  EXPECT_LT(covered_fraction(image, cv::Rect(0, 237, 320, 3), options.shading), 0.01);
}

TEST(OffscreenRenderer, ImageIsUprightAndLitFromTheUpperLeft) {
  RenderOptions options;
  options.width = 200;
  options.height = 200;
  MAKE_RENDERER_OR_SKIP(renderer, options);
  // Red on top, blue below: row 0 of the image must be the top of the mesh.
  renderer->set_mesh(
      testing::make_ellipsoid(1.0f, 1.0f, 1.0f, 24, 32, {0.9f, 0.1f, 0.1f}, {0.1f, 0.1f, 0.9f}));
  const cv::Mat image = renderer->render(CameraPose::front());
  const cv::Vec3b top = image.at<cv::Vec3b>(60, 100);
  const cv::Vec3b bottom = image.at<cv::Vec3b>(140, 100);
  EXPECT_GT(top[2], top[0]) << "top should be red";
  EXPECT_GT(bottom[0], bottom[2]) << "bottom should be blue";
  // Key light from the upper left: the left side of the upper half is brighter than the right.
  const cv::Vec3b left = image.at<cv::Vec3b>(70, 60);
  const cv::Vec3b right = image.at<cv::Vec3b>(70, 140);
  EXPECT_GT(left[2], right[2] + 10);
}

TEST(OffscreenRenderer, MovingVerticesChangesTheImage) {
  RenderOptions options;
  options.width = 160;
  options.height = 160;
  MAKE_RENDERER_OR_SKIP(renderer, options);
  const RenderMesh mesh = testing::make_ellipsoid(1.0f, 1.0f, 1.0f);
  renderer->set_mesh(mesh);
  const Bounds frame = renderer->mesh_bounds();
  const cv::Mat before = renderer->render(CameraPose::front(), frame);
  // Squash the mesh to half its width: the sides become background, the camera stays put.
  std::vector<float> squashed = mesh.positions;
  for (std::size_t i = 0; i < squashed.size(); i += 3) squashed[i] *= 0.5f;
  renderer->update_positions(squashed);
  const cv::Mat after = renderer->render(CameraPose::front(), frame);
  const cv::Rect side(30, 70, 15, 20);
  EXPECT_GT(covered_fraction(before, side, options.shading), 0.99);
  EXPECT_LT(covered_fraction(after, side, options.shading), 0.01);
  EXPECT_THROW(renderer->update_positions(std::vector<float>(6, 0.0f)), std::invalid_argument);
}

TEST(OffscreenRenderer, ResizeChangesTheOutputSize) {
  RenderOptions options;
  options.width = 64;
  options.height = 48;
  MAKE_RENDERER_OR_SKIP(renderer, options);
  renderer->set_mesh(testing::make_ellipsoid(1.0f, 1.0f, 1.0f));
  renderer->resize(101, 77);  // odd sizes: rows are not 4-byte aligned
  const cv::Mat image = renderer->render(CameraPose::three_quarter());
  EXPECT_EQ(image.cols, 101);
  EXPECT_EQ(image.rows, 77);
  EXPECT_GT(covered_fraction(image, cv::Rect(45, 33, 10, 10), options.shading), 0.99);
}

TEST(OffscreenRenderer, TexturedVerticesShowTheTextureTheShortWayAcrossItsSeam) {
  RenderOptions options;
  options.width = 200;
  options.height = 200;
  MAKE_RENDERER_OR_SKIP(renderer, options);
  // u runs around the ellipsoid from its front (phi = 0, where the texture's seam is): red on
  // the subject's left (u < 0.45, image right), blue on the right, a green band at the back.
  // A triangle across the seam that went the long way round would paint the front green.
  RenderMesh mesh =
      testing::make_ellipsoid(1.0f, 1.0f, 1.0f, 24, 32, {0.9f, 0.9f, 0.9f}, {0.9f, 0.9f, 0.9f});
  const int segments = 32;
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    const auto s = static_cast<float>(v % static_cast<std::size_t>(segments));
    const bool lower_quarter = mesh.positions[3 * v + 1] < -0.7f;  // untextured: its colour
    const float nan = std::numeric_limits<float>::quiet_NaN();
    mesh.texcoords.push_back(lower_quarter ? nan : s / segments);
    mesh.texcoords.push_back(lower_quarter ? nan : 0.5f);
  }
  mesh.texture.width = 64;
  mesh.texture.height = 4;
  for (int row = 0; row < 4; ++row)
    for (int x = 0; x < 64; ++x) {
      const double u = (x + 0.5) / 64;
      const bool green = u > 0.45 && u < 0.55;
      mesh.texture.rgb.insert(mesh.texture.rgb.end(), {std::uint8_t(!green && u < 0.5 ? 230 : 0),
                                                       std::uint8_t(green ? 230 : 0),
                                                       std::uint8_t(!green && u >= 0.5 ? 230 : 0)});
    }
  renderer->set_mesh(mesh);
  const cv::Mat image = renderer->render(CameraPose::front());
  const cv::Vec3b right = image.at<cv::Vec3b>(100, 140), left = image.at<cv::Vec3b>(100, 60);
  EXPECT_GT(right[2], right[0] + 50) << "the subject's left (image right) should be red";
  EXPECT_GT(left[0], left[2] + 50) << "the subject's right (image left) should be blue";
  int green = 0;
  for (int y = 20; y < 150; ++y)
    for (int x = 20; x < 180; ++x) {
      const cv::Vec3b p = image.at<cv::Vec3b>(y, x);
      if (p[1] > p[0] + 30 && p[1] > p[2] + 30) ++green;
    }
  EXPECT_EQ(green, 0) << "the seam's triangles went the long way round the texture";
  // The untextured bottom shows its vertex colour: light grey, not red or blue.
  const cv::Vec3b bottom = image.at<cv::Vec3b>(165, 100);
  EXPECT_LT(std::abs(bottom[0] - bottom[2]), 12);
  EXPECT_LT(std::abs(bottom[1] - bottom[2]), 12);
  EXPECT_GT(bottom[1], 60);
  // Coordinates without a texture are a bad mesh.
  mesh.texture = {};
  EXPECT_THROW(renderer->set_mesh(mesh), std::invalid_argument);
}

TEST(OffscreenRenderer, RejectsABadMesh) {
  RenderOptions options;
  options.width = 32;
  options.height = 32;
  MAKE_RENDERER_OR_SKIP(renderer, options);
  RenderMesh mesh = testing::make_ellipsoid(1.0f, 1.0f, 1.0f, 4, 4);
  mesh.triangles.back() = 100000;
  EXPECT_THROW(renderer->set_mesh(mesh), std::invalid_argument);
}

}  // namespace
}  // namespace rostro::render
