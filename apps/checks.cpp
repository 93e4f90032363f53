#include "apps/checks.hpp"

#include <fmt/format.h>

#include <cmath>

#include "facecore/error.hpp"
#include "facecore/fap_frame.hpp"

namespace rostro::app {

void check_fps(double fps, const std::string& option) {
  if (!valid_fps(fps))
    throw InputError(fmt::format("{} {}: expected a frame rate in (0, {}]", option, fps, kMaxFps));
}

void check_seconds(double seconds, const std::string& option, double max) {
  if (!(seconds > 0.0 && seconds <= max))
    throw InputError(
        fmt::format("{} {}: expected a duration in (0, {}] seconds", option, seconds, max));
}

}  // namespace rostro::app
