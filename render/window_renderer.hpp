#pragma once
// The on-screen back end: a GLFW window with an OpenGL 3.3 core context and the same
// GlMeshDrawer as the offscreen renderer, so a head in a window looks exactly like a video.
// The context is made through EGL (under X11 as under Wayland), like the offscreen one, so
// both can be used from one thread.

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "render/camera.hpp"
#include "render/gl_mesh_drawer.hpp"
#include "render/render_mesh.hpp"

struct GLFWwindow;

namespace rostro::render {

struct WindowOptions {
  int width = 960;
  int height = 720;
  std::string title = "rostro";
  int samples = 4;
  bool vsync = true;
  Shading shading;
  // Starts the RenderUnavailable message when there is no display ("no display for ...").
  std::string no_display = "no display for an OpenGL window";
};

// The keys a window reports; Quit is Q or Escape (or closing the window), Save is Ctrl+S.
// Every press is queued, so none is lost between two frames.
enum class WindowKey { Space, Left, Right, Up, Down, Home, PageUp, PageDown, Save, Quit };

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
  // For a user interface drawn over the head (rostro edit): draws the head into the
  // rectangle (x, y from the lower left, in framebuffer pixels) without showing it yet;
  // present() shows the finished frame.
  void draw_into(const CameraPose& pose, const Bounds& frame, int x, int y, int width, int height);
  void present();
  // The framebuffer's size in pixels (it may differ from the window's on a HiDPI screen).
  void framebuffer_size(int& width, int& height) const;
  GLFWwindow* glfw_window() const;
  // Handles window events without drawing.
  void poll();
  // The keys pressed since the last call, oldest first.
  std::vector<WindowKey> take_keys();
  void set_title(const std::string& title);
  // True once the user closed the window or pressed Q or Escape.
  bool should_close() const;
  const Bounds& mesh_bounds() const;

 private:
  struct Window;
  WindowOptions options_;
  std::unique_ptr<Window> window_;
};

}  // namespace rostro::render
