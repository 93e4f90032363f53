#pragma once
// The on-screen view of `rostro live`: a GLFW window showing the composited view (camera
// image with markers beside the animated head, figures and key help), and the keys:
//   C calibrate neutral now, R start/stop recording a .fap, T reset tracking, Q/Esc quit.
// The head itself is rendered offscreen by the pipeline (the same renderer as videos, an EGL
// context) on the thread that also draws the window; the window only shows the finished
// image, so it needs nothing newer than OpenGL 2.1. Its context is made through EGL as well:
// GLVND lets one thread switch between EGL contexts, but not from a GLX context to an EGL one.

#include <memory>
#include <string>

#include "live/pipeline.hpp"

namespace rostro::live {

class LiveWindow : public LiveView {
 public:
  // Throws render::RenderUnavailable when there is no display.
  LiveWindow(Pipeline& pipeline, const std::string& title);
  ~LiveWindow() override;
  LiveWindow(const LiveWindow&) = delete;
  LiveWindow& operator=(const LiveWindow&) = delete;

  void show(const ViewFrame& frame) override;
  bool poll() override;

 private:
  struct Glfw;
  std::unique_ptr<Glfw> glfw_;
};

}  // namespace rostro::live
