#pragma once
// GLFW is process-wide: glfwInit/glfwTerminate are counted here, so that several windows
// (the live view, a playback window) can come and go. Every GLFW error is remembered, so a
// failure can say what GLFW said.

#include <string>

namespace rostro::render {

class GlfwSession {
 public:
  // Throws RenderUnavailable, starting with `no_display`, when GLFW cannot start (no X11 or
  // Wayland display).
  explicit GlfwSession(const std::string& no_display);
  ~GlfwSession();
  GlfwSession(const GlfwSession&) = delete;
  GlfwSession& operator=(const GlfwSession&) = delete;

  // "GLFW error 65544: X11: The DISPLAY environment variable is missing", or "".
  static std::string last_error();
};

}  // namespace rostro::render
