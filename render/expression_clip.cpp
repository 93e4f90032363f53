#include "render/expression_clip.hpp"

#include <cmath>
#include <numbers>
#include <string>

#include "facecore/error.hpp"

namespace rostro::render {

FapStream expression_clip(int select, int intensity, const ClipTiming& timing) {
  if (select < 1 || select > 6) {
    throw InputError("expression " + std::to_string(select) + " is outside 1..6");
  }
  if (intensity < 0 || intensity > 63) {
    throw InputError("expression intensity " + std::to_string(intensity) + " is outside 0..63");
  }
  if (!(timing.fps > 0.0) || timing.hold_neutral_s < 0.0 || timing.ramp_s < 0.0 ||
      timing.hold_s < 0.0) {
    throw InputError("expression clip: the frame rate must be positive and durations >= 0");
  }
  FapStream stream;
  stream.header.name = "expression";
  stream.header.fps = timing.fps;
  const double total = timing.hold_neutral_s + timing.ramp_s + timing.hold_s;
  const long count = std::max(1L, std::lround(total * timing.fps));
  for (long k = 0; k < count; ++k) {
    const double t = static_cast<double>(k) / timing.fps;
    double weight = 1.0;
    if (t < timing.hold_neutral_s) {
      weight = 0.0;
    } else if (t < timing.hold_neutral_s + timing.ramp_s) {
      const double u = (t - timing.hold_neutral_s) / timing.ramp_s;
      weight = (1.0 - std::cos(std::numbers::pi * u)) / 2.0;
    }
    FapFrame frame;
    frame.index = k;
    frame.time_s = t;
    ExpressionParams e;
    e.select1 = select;
    e.intensity1 = static_cast<int>(std::lround(weight * intensity));
    frame.set_expression(e);
    stream.frames.push_back(frame);
  }
  stream.header.frame_count = count;
  return stream;
}

}  // namespace rostro::render
