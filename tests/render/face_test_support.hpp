#pragma once
// Shared helpers for the tests that render the default head.

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <string>

#include "facecore/expression_library.hpp"
#include "facecore/face_model.hpp"
#include "render/camera.hpp"
#include "render/face_renderer.hpp"
#include "render/render_error.hpp"

namespace rostro::render::testing {

// The default head and expression library, loaded once for the whole suite.
struct DefaultHead {
  FaceModel model;
  ExpressionLibrary library;
  static const DefaultHead& get() {
    static const DefaultHead head{load_default_face_model(), ExpressionLibrary::load_default()};
    return head;
  }
};

inline std::unique_ptr<FaceRenderer> make_face_renderer(int width, int height, std::string& why) {
  const DefaultHead& head = DefaultHead::get();
  RenderOptions options;
  options.width = width;
  options.height = height;
  try {
    return std::make_unique<FaceRenderer>(head.model, &head.library, options);
  } catch (const RenderUnavailable& e) {
    why = e.what();
    return nullptr;
  }
}

// Where a model point lands in the image (x right, y down, pixels).
inline cv::Point2d project(const FaceRenderer& face, const CameraPose& pose, int width, int height,
                           const Eigen::Vector3d& point) {
  const CameraMatrices m = frame_camera(pose, face.framing(), static_cast<double>(width) / height);
  const Eigen::Vector4f clip = m.projection * m.view * point.cast<float>().homogeneous();
  const double x = clip.x() / clip.w();
  const double y = clip.y() / clip.w();
  return {(x + 1.0) / 2.0 * width, (1.0 - y) / 2.0 * height};
}

inline bool is_background(const cv::Vec3b& pixel, const Shading& shading = {}) {
  for (int c = 0; c < 3; ++c) {
    const double expected = shading.background[static_cast<std::size_t>(2 - c)] * 255.0;
    if (std::abs(pixel[c] - expected) > 2.0) return false;
  }
  return true;
}

inline double covered_fraction(const cv::Mat& image, const cv::Rect& area) {
  int covered = 0;
  for (int y = area.y; y < area.y + area.height; ++y) {
    for (int x = area.x; x < area.x + area.width; ++x) {
      if (!is_background(image.at<cv::Vec3b>(y, x))) ++covered;
    }
  }
  return static_cast<double>(covered) / area.area();
}

}  // namespace rostro::render::testing

#define MAKE_FACE_RENDERER_OR_SKIP(var, width, height)                                      \
  std::string why_unavailable;                                                              \
  auto var = ::rostro::render::testing::make_face_renderer(width, height, why_unavailable); \
  if (!var) GTEST_SKIP() << "no headless OpenGL (EGL) here: " << why_unavailable
