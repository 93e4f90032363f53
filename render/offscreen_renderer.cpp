#include "render/offscreen_renderer.hpp"

#include <algorithm>
#include <cstdio>
#include <opencv2/core.hpp>
#include <stdexcept>
#include <string>

#include "render/egl_context.hpp"
#include "render/gl_api.hpp"
#include "render/render_error.hpp"

namespace rostro::render {

struct OffscreenRenderer::Gl {
  EglContext context;  // declared first: destroyed last
  std::unique_ptr<GlMeshDrawer> drawer;
  // Multisampled target (when samples > 1) resolved into a single-sample one for reading.
  GLuint msaa_fbo = 0, msaa_color = 0, msaa_depth = 0;
  GLuint resolve_fbo = 0, resolve_color = 0, resolve_depth = 0;
};

namespace {

void check_size(int width, int height) {
  if (width < 1 || height < 1 || width > 16384 || height > 16384) {
    throw std::invalid_argument("render size " + std::to_string(width) + "x" +
                                std::to_string(height) + " is outside 1..16384");
  }
}

std::string hex(unsigned value) {
  char buffer[16];
  std::snprintf(buffer, sizeof buffer, "0x%04x", value);
  return buffer;
}

void check_framebuffer(const char* which) {
  const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    throw RenderUnavailable(std::string("OpenGL ") + which + " framebuffer is incomplete (" +
                            hex(status) + ")");
  }
}

}  // namespace

OffscreenRenderer::OffscreenRenderer(const RenderOptions& options) : options_(options) {
  check_size(options.width, options.height);
  gl_ = std::make_unique<Gl>();
  gl_->drawer = std::make_unique<GlMeshDrawer>();
  GLint max_samples = 1;
  glGetIntegerv(GL_MAX_SAMPLES, &max_samples);
  samples_ = std::clamp(options.samples, 1, std::max(1, static_cast<int>(max_samples)));
  create_framebuffers();
}

OffscreenRenderer::~OffscreenRenderer() {
  if (!gl_) return;
  gl_->context.make_current();
  destroy_framebuffers();
  gl_->drawer.reset();
}

void OffscreenRenderer::create_framebuffers() {
  const GLsizei w = options_.width;
  const GLsizei h = options_.height;
  auto renderbuffer = [&](GLenum format, GLsizei samples) {
    GLuint rb = 0;
    glGenRenderbuffers(1, &rb);
    glBindRenderbuffer(GL_RENDERBUFFER, rb);
    if (samples > 1) {
      glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, format, w, h);
    } else {
      glRenderbufferStorage(GL_RENDERBUFFER, format, w, h);
    }
    return rb;
  };
  glGenFramebuffers(1, &gl_->resolve_fbo);
  glBindFramebuffer(GL_FRAMEBUFFER, gl_->resolve_fbo);
  gl_->resolve_color = renderbuffer(GL_RGBA8, 1);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                            gl_->resolve_color);
  if (samples_ <= 1) {
    gl_->resolve_depth = renderbuffer(GL_DEPTH_COMPONENT24, 1);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER,
                              gl_->resolve_depth);
  }
  check_framebuffer("resolve");
  if (samples_ > 1) {
    glGenFramebuffers(1, &gl_->msaa_fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, gl_->msaa_fbo);
    gl_->msaa_color = renderbuffer(GL_RGBA8, samples_);
    gl_->msaa_depth = renderbuffer(GL_DEPTH_COMPONENT24, samples_);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                              gl_->msaa_color);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER,
                              gl_->msaa_depth);
    check_framebuffer("multisampled");
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void OffscreenRenderer::destroy_framebuffers() {
  for (GLuint* fbo : {&gl_->msaa_fbo, &gl_->resolve_fbo}) {
    if (*fbo != 0) glDeleteFramebuffers(1, fbo);
    *fbo = 0;
  }
  for (GLuint* rb :
       {&gl_->msaa_color, &gl_->msaa_depth, &gl_->resolve_color, &gl_->resolve_depth}) {
    if (*rb != 0) glDeleteRenderbuffers(1, rb);
    *rb = 0;
  }
}

void OffscreenRenderer::resize(int width, int height) {
  check_size(width, height);
  if (width == options_.width && height == options_.height) return;
  gl_->context.make_current();
  destroy_framebuffers();
  options_.width = width;
  options_.height = height;
  create_framebuffers();
}

void OffscreenRenderer::set_mesh(const RenderMesh& mesh) {
  gl_->context.make_current();
  gl_->drawer->set_mesh(mesh);
}

void OffscreenRenderer::update_positions(std::span<const float> positions) {
  gl_->context.make_current();
  gl_->drawer->update_positions(positions);
}

const Bounds& OffscreenRenderer::mesh_bounds() const {
  return gl_->drawer->mesh_bounds();
}

std::string OffscreenRenderer::description() const {
  return gl_->context.description() + ", " + std::to_string(samples_) + "x multisampling";
}

cv::Mat OffscreenRenderer::render(const CameraPose& pose) {
  return render(pose, mesh_bounds());
}

cv::Mat OffscreenRenderer::render(const CameraPose& pose, const Bounds& frame) {
  cv::Mat bgr;
  render_into(pose, frame, bgr);
  return bgr;
}

void OffscreenRenderer::render_into(const CameraPose& pose, const Bounds& frame, cv::Mat& bgr) {
  gl_->context.make_current();
  const int w = options_.width;
  const int h = options_.height;
  const CameraMatrices camera = frame_camera(pose, frame, static_cast<double>(w) / h);
  const GLuint target = samples_ > 1 ? gl_->msaa_fbo : gl_->resolve_fbo;
  glBindFramebuffer(GL_FRAMEBUFFER, target);
  gl_->drawer->draw(camera, w, h, options_.shading);
  if (samples_ > 1) {
    glBindFramebuffer(GL_READ_FRAMEBUFFER, gl_->msaa_fbo);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, gl_->resolve_fbo);
    glBlitFramebuffer(0, 0, w, h, 0, 0, w, h, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  }
  glBindFramebuffer(GL_READ_FRAMEBUFFER, gl_->resolve_fbo);
  bgr.create(h, w, CV_8UC3);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glPixelStorei(GL_PACK_ROW_LENGTH, static_cast<GLint>(bgr.step[0] / 3));
  glReadPixels(0, 0, w, h, GL_BGR, GL_UNSIGNED_BYTE, bgr.data);
  glPixelStorei(GL_PACK_ROW_LENGTH, 0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  const GLenum error = glGetError();
  if (error != GL_NO_ERROR) {
    throw RenderUnavailable("OpenGL error " + hex(error) + " while rendering");
  }
  cv::flip(bgr, bgr, 0);  // OpenGL's row 0 is the bottom of the image
}

}  // namespace rostro::render
