#include "render/window_renderer.hpp"

// glcorearb.h first: GLFW then leaves the OpenGL headers alone.
#include "render/gl_api.hpp"
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <optional>
#include <string>
#include <utility>

#include "render/glfw_session.hpp"
#include "render/render_error.hpp"

namespace rostro::render {
namespace {

// The GLFW keys a window reports, and what it reports them as.
constexpr std::pair<int, WindowKey> kKeys[] = {
    {GLFW_KEY_SPACE, WindowKey::Space},    {GLFW_KEY_LEFT, WindowKey::Left},
    {GLFW_KEY_RIGHT, WindowKey::Right},    {GLFW_KEY_UP, WindowKey::Up},
    {GLFW_KEY_DOWN, WindowKey::Down},      {GLFW_KEY_HOME, WindowKey::Home},
    {GLFW_KEY_PAGE_UP, WindowKey::PageUp}, {GLFW_KEY_PAGE_DOWN, WindowKey::PageDown},
    {GLFW_KEY_Q, WindowKey::Quit},         {GLFW_KEY_ESCAPE, WindowKey::Quit}};

std::optional<WindowKey> window_key(int key, int mods) {
  if (key == GLFW_KEY_S && (mods & GLFW_MOD_CONTROL) != 0) return WindowKey::Save;
  for (const auto& [glfw, ours] : kKeys) {
    if (glfw == key) return ours;
  }
  return std::nullopt;
}

}  // namespace

struct WindowRenderer::Window {
  explicit Window(const std::string& no_display) : glfw(no_display) {}
  ~Window() {
    if (handle == nullptr) return;
    glfwMakeContextCurrent(handle);
    drawer.reset();
    glfwDestroyWindow(handle);
  }
  GlfwSession glfw;  // declared first: outlives the window
  GLFWwindow* handle = nullptr;
  std::unique_ptr<GlMeshDrawer> drawer;
  std::vector<WindowKey> keys;
};

WindowRenderer::WindowRenderer(const WindowOptions& options)
    : options_(options), window_(std::make_unique<Window>(options.no_display)) {
  glfwDefaultWindowHints();
  glfwWindowHint(GLFW_CONTEXT_CREATION_API, GLFW_EGL_CONTEXT_API);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_SAMPLES, options.samples > 1 ? options.samples : 0);
  window_->handle =
      glfwCreateWindow(options.width, options.height, options.title.c_str(), nullptr, nullptr);
  if (window_->handle == nullptr) {
    throw RenderUnavailable("cannot open an OpenGL 3.3 window (" + GlfwSession::last_error() + ")");
  }
  glfwMakeContextCurrent(window_->handle);
  glfwSwapInterval(options.vsync ? 1 : 0);
  glfwSetWindowUserPointer(window_->handle, window_.get());
  glfwSetKeyCallback(window_->handle, [](GLFWwindow* w, int key, int, int action, int mods) {
    if (action == GLFW_RELEASE) return;  // presses and auto-repeats (holding an arrow seeks on)
    const std::optional<WindowKey> k = window_key(key, mods);
    if (!k) return;
    static_cast<Window*>(glfwGetWindowUserPointer(w))->keys.push_back(*k);
    if (*k == WindowKey::Quit) glfwSetWindowShouldClose(w, GLFW_TRUE);
  });
  window_->drawer = std::make_unique<GlMeshDrawer>();
  if (options.samples > 1) glEnable(GL_MULTISAMPLE);
}

WindowRenderer::~WindowRenderer() = default;

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
  int width = 0;
  int height = 0;
  framebuffer_size(width, height);
  if (width > 0 && height > 0) {
    draw_into(pose, frame, 0, 0, width, height);
    present();
  }
  glfwPollEvents();
}

void WindowRenderer::draw_into(const CameraPose& pose, const Bounds& frame, int x, int y, int width,
                               int height) {
  glfwMakeContextCurrent(window_->handle);
  if (width <= 0 || height <= 0) return;
  const CameraMatrices camera = frame_camera(pose, frame, static_cast<double>(width) / height);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  window_->drawer->draw(camera, width, height, options_.shading, x, y);
}

void WindowRenderer::present() {
  glfwSwapBuffers(window_->handle);
}

void WindowRenderer::framebuffer_size(int& width, int& height) const {
  glfwGetFramebufferSize(window_->handle, &width, &height);
}

GLFWwindow* WindowRenderer::glfw_window() const {
  return window_->handle;
}

void WindowRenderer::poll() {
  glfwPollEvents();
}

std::vector<WindowKey> WindowRenderer::take_keys() {
  std::vector<WindowKey> keys;
  keys.swap(window_->keys);
  return keys;
}

void WindowRenderer::set_title(const std::string& title) {
  glfwSetWindowTitle(window_->handle, title.c_str());
}

bool WindowRenderer::should_close() const {
  return glfwWindowShouldClose(window_->handle) == GLFW_TRUE;
}

}  // namespace rostro::render
