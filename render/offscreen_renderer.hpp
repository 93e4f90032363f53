#pragma once
// Renders a mesh headless into an image: an EGL context, a multisampled framebuffer object,
// and the shared GlMeshDrawer. The output is a BGR cv::Mat (OpenCV's channel order) with row
// 0 at the top. One renderer belongs to one thread at a time.

#include <memory>
#include <opencv2/core.hpp>
#include <span>
#include <string>

#include "render/camera.hpp"
#include "render/gl_mesh_drawer.hpp"
#include "render/render_mesh.hpp"

namespace rostro::render {

struct RenderOptions {
  int width = 640;
  int height = 480;
  int samples = 4;  // multisampling; 1 turns it off (clamped to what the driver offers)
  Shading shading;
};

class OffscreenRenderer {
 public:
  // Throws RenderUnavailable when no headless OpenGL context exists, std::invalid_argument
  // for a size outside 1..16384.
  explicit OffscreenRenderer(const RenderOptions& options = {});
  ~OffscreenRenderer();
  OffscreenRenderer(const OffscreenRenderer&) = delete;
  OffscreenRenderer& operator=(const OffscreenRenderer&) = delete;

  void set_mesh(const RenderMesh& mesh);
  void update_positions(std::span<const float> positions);

  // Frames the camera on the bounds of the mesh given to set_mesh (so the view does not
  // follow the face as it moves), or on `frame` when given.
  cv::Mat render(const CameraPose& pose);
  cv::Mat render(const CameraPose& pose, const Bounds& frame);
  // The same, reusing `bgr`'s storage (no allocation per frame in a video loop).
  void render_into(const CameraPose& pose, const Bounds& frame, cv::Mat& bgr);

  void resize(int width, int height);
  int width() const { return options_.width; }
  int height() const { return options_.height; }
  int samples() const { return samples_; }
  const Bounds& mesh_bounds() const;
  Shading& shading() { return options_.shading; }
  // The OpenGL renderer and how the context was made, for logs and benchmark reports.
  std::string description() const;

 private:
  struct Gl;
  RenderOptions options_;
  int samples_ = 1;
  std::unique_ptr<Gl> gl_;
  void create_framebuffers();
  void destroy_framebuffers();
};

}  // namespace rostro::render
