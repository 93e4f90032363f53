#include "render/glfw_session.hpp"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <mutex>

#include "render/render_error.hpp"

namespace rostro::render {
namespace {

std::mutex users_mutex;  // guards users, and so glfwInit/glfwTerminate
int users = 0;
std::mutex error_mutex;  // guards last_message
std::string last_message;

void remember_error(int code, const char* description) {
  std::lock_guard lock(error_mutex);
  last_message = "GLFW error " + std::to_string(code) + ": " + (description ? description : "");
}

}  // namespace

GlfwSession::GlfwSession(const std::string& no_display) {
  std::lock_guard lock(users_mutex);
  if (users == 0) {
    glfwSetErrorCallback(remember_error);
    if (glfwInit() != GLFW_TRUE) throw RenderUnavailable(no_display + " (" + last_error() + ")");
  }
  ++users;
}

GlfwSession::~GlfwSession() {
  std::lock_guard lock(users_mutex);
  if (--users == 0) glfwTerminate();
}

std::string GlfwSession::last_error() {
  std::lock_guard lock(error_mutex);
  return last_message;
}

}  // namespace rostro::render
