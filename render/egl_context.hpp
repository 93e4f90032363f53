#pragma once
// A headless OpenGL 3.3 core context through EGL: no window system, no display server.
// Tries, in order, Mesa's surfaceless platform (it uses a GPU render node when there is one
// and llvmpipe otherwise), the EGL device platform (NVIDIA's driver), then the default
// display with a 1x1 pbuffer. Rendering goes to framebuffer objects, not to a surface.

#include <string>

namespace rostro::render {

class EglContext {
 public:
  // Throws RenderUnavailable, saying which attempts failed, when no context can be made.
  EglContext();
  ~EglContext();
  EglContext(const EglContext&) = delete;
  EglContext& operator=(const EglContext&) = delete;

  // Makes the context current on the calling thread (the constructor already did).
  void make_current();
  // "llvmpipe (LLVM 15...)" or the GPU's name, and how the display was obtained.
  const std::string& description() const { return description_; }

 private:
  void* display_ = nullptr;
  void* context_ = nullptr;
  void* surface_ = nullptr;
  std::string description_;
};

}  // namespace rostro::render
