#include "script/head_actions.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace rostro::script {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kActivityRamp = 0.3;  // seconds over which idle noise fades around an action

double smoothstep(double u) {
  u = std::clamp(u, 0.0, 1.0);
  return u * u * (3.0 - 2.0 * u);
}

}  // namespace

Direction HeadActions::pose(const HeadAction& a, double t) {
  Direction d;
  if (t < a.at || t >= a.end) return d;
  const double u = std::isfinite(a.end) ? (t - a.at) / (a.end - a.at) : 0.0;
  const double n = static_cast<double>(a.count);
  switch (a.kind) {
    case HeadKind::Nod:
      d.pitch_deg = a.amplitude_deg * std::pow(std::sin(kPi * n * u), 2);
      break;
    case HeadKind::Shake:
      d.yaw_deg = a.amplitude_deg * std::sin(2 * kPi * n * u) * std::sin(kPi * u);
      break;
    case HeadKind::Tilt:
    case HeadKind::Turn: {
      double w = a.ramp > 0 ? smoothstep((t - a.at) / a.ramp) : 1.0;
      if (std::isfinite(a.end) && a.ramp > 0) w = std::min(w, smoothstep((a.end - t) / a.ramp));
      d.yaw_deg = w * a.target.yaw_deg;
      d.pitch_deg = w * a.target.pitch_deg;
      d.roll_deg = w * a.target.roll_deg;
      break;
    }
    case HeadKind::Still:
      break;
  }
  return d;
}

HeadActions::HeadActions(const std::vector<HeadAction>& actions, long frames, double fps,
                         const speech::HeadSettings& settings, std::uint64_t seed, bool noise)
    : frames_(static_cast<std::size_t>(std::max(0L, frames))) {
  moves_ = noise || !actions.empty();
  if (noise) {
    const auto track = speech::head_track(frames, fps, settings, seed * 3 + 13);
    for (std::size_t k = 0; k < frames_.size(); ++k)
      frames_[k].noise = {track[k].yaw_deg, track[k].pitch_deg, track[k].roll_deg};
  }
  for (const HeadAction& a : actions) {
    for (std::size_t k = 0; k < frames_.size(); ++k) {
      const double t = static_cast<double>(k) / fps;
      HeadFrame& f = frames_[k];
      const Direction d = pose(a, t);
      f.action.yaw_deg += d.yaw_deg;
      f.action.pitch_deg += d.pitch_deg;
      f.action.roll_deg += d.roll_deg;
      const double outside = t < a.at ? a.at - t : t >= a.end ? t - a.end : 0.0;
      f.activity = std::max(f.activity, std::clamp(1.0 - outside / kActivityRamp, 0.0, 1.0));
    }
  }
}

}  // namespace rostro::script
