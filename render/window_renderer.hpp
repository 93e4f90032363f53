#pragma once
// The on-screen back end for live use: a GLFW window with an OpenGL 3.3 core context and the
// same GlMeshDrawer as the offscreen renderer, so a live avatar looks exactly like a video.

#include <memory>
#include <span>
#include <string>

#include "render/camera.hpp"
#include "render/gl_mesh_drawer.hpp"
#include "render/render_mesh.hpp"

namespace rostro::render {

struct WindowOptions {
  int width = 960;
  int height = 720;
  std::string title = "rostro";
  int samples = 4;
  bool vsync = true;
  Shading shading;
};

class WindowRenderer {
 public:
  // Throws RenderUnavailable when there is no display or no OpenGL 3.3 core context.
  explicit WindowRenderer(const WindowOptions& options = {});
  ~WindowRenderer();
  WindowRenderer(const WindowRenderer&) = delete;
  WindowRenderer& operator=(const WindowRenderer&) = delete;

  void set_mesh(const RenderMesh& mesh);
  void update_positions(std::span<const float> positions);

  // Draws one frame framed on the mesh's bounds, shows it and handles window events.
  void draw(const CameraPose& pose);
  void draw(const CameraPose& pose, const Bounds& frame);
  // True once the user closed the window or pressed Escape.
  bool should_close() const;
  const Bounds& mesh_bounds() const;

 private:
  struct Window;
  WindowOptions options_;
  std::unique_ptr<Window> window_;
};

}  // namespace rostro::render
