#include "live/live_window.hpp"

#define GLFW_INCLUDE_NONE
#include <GL/gl.h>
#include <GLFW/glfw3.h>

#include "render/glfw_session.hpp"
#include "render/render_error.hpp"

namespace rostro::live {

struct LiveWindow::Glfw {
  render::GlfwSession session{"no display for the live window; use --headless"};
  Pipeline* pipeline = nullptr;
  GLFWwindow* window = nullptr;
  bool quit = false;
};

LiveWindow::LiveWindow(Pipeline& pipeline, const std::string& title)
    : glfw_(std::make_unique<Glfw>()) {
  glfw_->pipeline = &pipeline;
  glfwDefaultWindowHints();
  glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
  // The head is rendered offscreen through EGL on this same thread. With GLVND, a thread
  // that has a GLX context current cannot make an EGL context current (EGL_BAD_ACCESS), so
  // the window's context is made through EGL too (as it always is under Wayland).
  glfwWindowHint(GLFW_CONTEXT_CREATION_API, GLFW_EGL_CONTEXT_API);
  glfw_->window = glfwCreateWindow(1280, 560, title.c_str(), nullptr, nullptr);
  if (!glfw_->window) {
    throw render::RenderUnavailable("could not open the live window (" +
                                    render::GlfwSession::last_error() + "); use --headless");
  }
  glfwSetWindowUserPointer(glfw_->window, glfw_.get());
  glfwSetKeyCallback(glfw_->window, [](GLFWwindow* w, int key, int, int action, int) {
    if (action != GLFW_PRESS) return;
    auto* g = static_cast<Glfw*>(glfwGetWindowUserPointer(w));
    switch (key) {
      case GLFW_KEY_C:
        g->pipeline->calibrate_now();
        break;
      case GLFW_KEY_R:
        g->pipeline->toggle_recording();
        break;
      case GLFW_KEY_T:
        g->pipeline->reset_tracking();
        break;
      case GLFW_KEY_Q:
      case GLFW_KEY_ESCAPE:
        g->quit = true;
        break;
      default:
        break;
    }
  });
  glfwMakeContextCurrent(glfw_->window);
  glfwSwapInterval(0);  // never wait for vsync: the view must not slow the pipeline
}

LiveWindow::~LiveWindow() {
  glfwDestroyWindow(glfw_->window);
}

void LiveWindow::show(const ViewFrame& frame) {
  // The pipeline's offscreen renderer has its own (EGL) context: take ours back first.
  glfwMakeContextCurrent(glfw_->window);
  if (frame.image.cols != 0) {
    int w = 0, h = 0;
    glfwGetWindowSize(glfw_->window, &w, &h);
    if (w != frame.image.cols || h != frame.image.rows)
      glfwSetWindowSize(glfw_->window, frame.image.cols, frame.image.rows);
    int fw = 0, fh = 0;
    glfwGetFramebufferSize(glfw_->window, &fw, &fh);
    glViewport(0, 0, fw, fh);
    glClear(GL_COLOR_BUFFER_BIT);
    // Row 0 of the image is the top: draw from the top-left corner downwards.
    glRasterPos2f(-1.f, 1.f);
    glPixelZoom(static_cast<float>(fw) / static_cast<float>(frame.image.cols),
                -static_cast<float>(fh) / static_cast<float>(frame.image.rows));
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glPixelStorei(GL_UNPACK_ROW_LENGTH, static_cast<GLint>(frame.image.step / 3));
    glDrawPixels(frame.image.cols, frame.image.rows, GL_BGR, GL_UNSIGNED_BYTE, frame.image.data);
  }
  glfwSwapBuffers(glfw_->window);
}

bool LiveWindow::poll() {
  glfwPollEvents();
  return !glfw_->quit && !glfwWindowShouldClose(glfw_->window);
}

}  // namespace rostro::live
