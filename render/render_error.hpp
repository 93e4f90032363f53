#pragma once
// The error raised when no OpenGL context can be had (no EGL display, no GL 3.3 driver, no
// window system). It is not bad input: callers may fall back, and tests skip on it.

#include <stdexcept>

namespace rostro::render {

class RenderUnavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace rostro::render
