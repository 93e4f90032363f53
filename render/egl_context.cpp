#include "render/egl_context.hpp"

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstring>
#include <string>
#include <vector>

#include "render/gl_api.hpp"
#include "render/render_error.hpp"

namespace rostro::render {
namespace {

bool has_extension(const char* list, const char* name) {
  if (list == nullptr) return false;
  const std::size_t n = std::strlen(name);
  for (const char* p = std::strstr(list, name); p != nullptr; p = std::strstr(p + 1, name)) {
    const bool starts = p == list || p[-1] == ' ';
    const bool ends = p[n] == ' ' || p[n] == '\0';
    if (starts && ends) return true;
  }
  return false;
}

std::string egl_error() {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "EGL error 0x%04x", static_cast<unsigned>(eglGetError()));
  return buffer;
}

struct Candidate {
  EGLDisplay display;
  std::string how;
};

std::vector<Candidate> candidate_displays(std::string& notes) {
  std::vector<Candidate> out;
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  auto get_platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
      eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (get_platform_display != nullptr && has_extension(client, "EGL_MESA_platform_surfaceless")) {
    EGLDisplay d =
        get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (d != EGL_NO_DISPLAY) out.push_back({d, "surfaceless"});
  }
  if (get_platform_display != nullptr && has_extension(client, "EGL_EXT_platform_device")) {
    auto query_devices =
        reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    EGLDeviceEXT devices[8];
    EGLint count = 0;
    if (query_devices != nullptr && query_devices(8, devices, &count)) {
      for (EGLint i = 0; i < count; ++i) {
        EGLDisplay d = get_platform_display(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
        if (d != EGL_NO_DISPLAY) out.push_back({d, "device " + std::to_string(i)});
      }
    }
  }
  EGLDisplay d = eglGetDisplay(EGL_DEFAULT_DISPLAY);
  if (d != EGL_NO_DISPLAY) out.push_back({d, "default display"});
  if (out.empty()) notes += "no EGL display; ";
  return out;
}

}  // namespace

EglContext::EglContext() {
  std::string notes;
  for (const Candidate& candidate : candidate_displays(notes)) {
    EGLint major = 0;
    EGLint minor = 0;
    if (!eglInitialize(candidate.display, &major, &minor)) {
      notes += candidate.how + ": eglInitialize failed (" + egl_error() + "); ";
      continue;
    }
    if (!eglBindAPI(EGL_OPENGL_API)) {
      notes += candidate.how + ": no desktop OpenGL; ";
      continue;
    }
    const EGLint config_attributes[] = {EGL_SURFACE_TYPE,
                                        EGL_PBUFFER_BIT,
                                        EGL_RENDERABLE_TYPE,
                                        EGL_OPENGL_BIT,
                                        EGL_RED_SIZE,
                                        8,
                                        EGL_GREEN_SIZE,
                                        8,
                                        EGL_BLUE_SIZE,
                                        8,
                                        EGL_NONE};
    EGLConfig config = nullptr;
    EGLint config_count = 0;
    eglChooseConfig(candidate.display, config_attributes, &config, 1, &config_count);
    const char* display_extensions = eglQueryString(candidate.display, EGL_EXTENSIONS);
    const bool configless = has_extension(display_extensions, "EGL_KHR_no_config_context") ||
                            has_extension(display_extensions, "EGL_MESA_configless_context");
    if (config_count == 0 && !configless) {
      notes += candidate.how + ": no RGB8 pbuffer config; ";
      continue;
    }
    const EGLint context_attributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                         3,
                                         EGL_CONTEXT_MINOR_VERSION,
                                         3,
                                         EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                         EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                         EGL_NONE};
    EGLContext context =
        eglCreateContext(candidate.display, config_count > 0 ? config : EGL_NO_CONFIG_KHR,
                         EGL_NO_CONTEXT, context_attributes);
    if (context == EGL_NO_CONTEXT) {
      notes += candidate.how + ": no OpenGL 3.3 core context (" + egl_error() + "); ";
      continue;
    }
    EGLSurface surface = EGL_NO_SURFACE;
    if (!has_extension(display_extensions, "EGL_KHR_surfaceless_context") && config_count > 0) {
      const EGLint pbuffer_attributes[] = {EGL_WIDTH, 1, EGL_HEIGHT, 1, EGL_NONE};
      surface = eglCreatePbufferSurface(candidate.display, config, pbuffer_attributes);
    }
    if (!eglMakeCurrent(candidate.display, surface, surface, context)) {
      notes += candidate.how + ": eglMakeCurrent failed (" + egl_error() + "); ";
      if (surface != EGL_NO_SURFACE) eglDestroySurface(candidate.display, surface);
      eglDestroyContext(candidate.display, context);
      continue;
    }
    display_ = candidate.display;
    context_ = context;
    surface_ = surface;
    const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    const auto* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
    description_ = std::string(renderer ? renderer : "unknown renderer") + ", OpenGL " +
                   (version ? version : "?") + ", EGL " + candidate.how;
    return;
  }
  throw RenderUnavailable("no headless OpenGL 3.3 context through EGL: " + notes);
}

EglContext::~EglContext() {
  // The display is not terminated: other contexts in this process may share it, and
  // eglTerminate would pull their resources away.
  eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  if (surface_ != nullptr) eglDestroySurface(display_, surface_);
  eglDestroyContext(display_, context_);
  eglReleaseThread();
}

void EglContext::make_current() {
  if (eglGetCurrentContext() == context_) return;
  if (!eglMakeCurrent(display_, surface_, surface_, context_)) {
    throw RenderUnavailable("eglMakeCurrent failed: " + egl_error());
  }
}

}  // namespace rostro::render
