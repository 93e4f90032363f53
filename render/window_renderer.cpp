#include "render/window_renderer.hpp"

// glcorearb.h first: GLFW then leaves the OpenGL headers alone.
#include "render/gl_api.hpp"
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <mutex>
#include <string>

#include "render/render_error.hpp"

namespace rostro::render {
namespace {

std::string& last_glfw_error() {
  static std::string message;
  return message;
}

void remember_glfw_error(int code, const char* description) {
  last_glfw_error() =
      "GLFW error " + std::to_string(code) + ": " + (description ? description : "");
}

// glfwInit/glfwTerminate are process-wide; windows count their users.
std::mutex glfw_mutex;
int glfw_users = 0;

void acquire_glfw() {
  std::lock_guard lock(glfw_mutex);
  if (glfw_users == 0) {
    glfwSetErrorCallback(remember_glfw_error);
    if (glfwInit() != GLFW_TRUE) {
      throw RenderUnavailable("no window system for an OpenGL window (" + last_glfw_error() + ")");
    }
  }
  ++glfw_users;
}

void release_glfw() {
  std::lock_guard lock(glfw_mutex);
  if (--glfw_users == 0) glfwTerminate();
}

}  // namespace

struct WindowRenderer::Window {
  GLFWwindow* handle = nullptr;
  std::unique_ptr<GlMeshDrawer> drawer;
};

WindowRenderer::WindowRenderer(const WindowOptions& options) : options_(options) {
  acquire_glfw();
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_SAMPLES, options.samples > 1 ? options.samples : 0);
  GLFWwindow* handle =
      glfwCreateWindow(options.width, options.height, options.title.c_str(), nullptr, nullptr);
  if (handle == nullptr) {
    release_glfw();
    throw RenderUnavailable("cannot open an OpenGL 3.3 window (" + last_glfw_error() + ")");
  }
  glfwMakeContextCurrent(handle);
  glfwSwapInterval(options.vsync ? 1 : 0);
  glfwSetKeyCallback(handle, [](GLFWwindow* w, int key, int, int action, int) {
    if (key == GLFW_KEY_ESCAPE && action == GLFW_PRESS) glfwSetWindowShouldClose(w, GLFW_TRUE);
  });
  window_ = std::make_unique<Window>();
  window_->handle = handle;
  try {
    window_->drawer = std::make_unique<GlMeshDrawer>();
  } catch (...) {
    glfwDestroyWindow(handle);
    release_glfw();
    throw;
  }
  if (options.samples > 1) glEnable(GL_MULTISAMPLE);
}

WindowRenderer::~WindowRenderer() {
  glfwMakeContextCurrent(window_->handle);
  window_->drawer.reset();
  glfwDestroyWindow(window_->handle);
  release_glfw();
}

void WindowRenderer::set_mesh(const RenderMesh& mesh) {
  glfwMakeContextCurrent(window_->handle);
  window_->drawer->set_mesh(mesh);
}

void WindowRenderer::update_positions(std::span<const float> positions) {
  glfwMakeContextCurrent(window_->handle);
  window_->drawer->update_positions(positions);
}

const Bounds& WindowRenderer::mesh_bounds() const {
  return window_->drawer->mesh_bounds();
}

void WindowRenderer::draw(const CameraPose& pose) {
  draw(pose, mesh_bounds());
}

void WindowRenderer::draw(const CameraPose& pose, const Bounds& frame) {
  glfwMakeContextCurrent(window_->handle);
  int width = 0;
  int height = 0;
  glfwGetFramebufferSize(window_->handle, &width, &height);
  if (width > 0 && height > 0) {
    const CameraMatrices camera = frame_camera(pose, frame, static_cast<double>(width) / height);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    window_->drawer->draw(camera, width, height, options_.shading);
    glfwSwapBuffers(window_->handle);
  }
  glfwPollEvents();
}

bool WindowRenderer::should_close() const {
  return glfwWindowShouldClose(window_->handle) == GLFW_TRUE;
}

}  // namespace rostro::render
