#include "script/eye_behaviour.hpp"

#include <algorithm>
#include <cmath>

namespace rostro::script {
namespace {

double smoothstep(double u) {
  u = std::clamp(u, 0.0, 1.0);
  return u * u * (3.0 - 2.0 * u);
}

Direction lerp(const Direction& a, const Direction& b, double w) {
  return {a.yaw_deg + w * (b.yaw_deg - a.yaw_deg), a.pitch_deg + w * (b.pitch_deg - a.pitch_deg),
          0.0};
}

double distance(const Direction& a, const Direction& b) {
  return std::hypot(a.yaw_deg - b.yaw_deg, a.pitch_deg - b.pitch_deg);
}

// Saccade duration for an amplitude (Eyes Alive: D0 + d x A), from behaviour.json.
double saccade_s(double amplitude_deg, const speech::SaccadeSettings& s) {
  return s.duration_base_s + s.duration_per_deg_s * amplitude_deg;
}

// The moving point of a pursuit at time t (linear between evenly spaced points).
Direction pursuit_point(const EyeAction& a, double t) {
  const double u = std::clamp((t - a.at) / (a.end - a.at), 0.0, 1.0);
  const double x = u * static_cast<double>(a.path.size() - 1);
  const auto i = std::min(static_cast<std::size_t>(x), a.path.size() - 2);
  return lerp(a.path[i], a.path[i + 1], x - static_cast<double>(i));
}

// Gaze (relative to the camera) during scripted action `a`, which took over from `from`.
Direction gaze_during(const EyeAction& a, const Direction& from, double t,
                      const speech::SaccadeSettings& s) {
  if (a.kind == EyeKind::Pursuit) {
    const Direction p = pursuit_point(a, t);
    const double d = saccade_s(distance(from, a.path.front()), s);
    return t < a.at + d ? lerp(from, p, smoothstep((t - a.at) / d)) : p;
  }
  const Direction& target = a.path.front();
  const double d = saccade_s(distance(from, target), s);
  if (t < a.at + d) return lerp(from, target, smoothstep((t - a.at) / d));
  if (t < a.end) return target;
  const double back = saccade_s(distance(target, {}), s);  // back to the camera
  return lerp(target, {}, smoothstep((t - a.end) / back));
}

speech::SaccadeSettings styled(speech::SaccadeSettings s, const std::string& style) {
  if (style == "listening") {  // longer fixations, smaller shifts
    s.mean_interval_s *= 1.6;
    s.mean_amplitude_deg *= 0.7;
  } else if (style == "thinking") {  // larger, rarer shifts (plus an upward, sideways bias)
    s.mean_interval_s *= 1.3;
    s.mean_amplitude_deg *= 1.5;
    s.max_amplitude_deg *= 1.5;
  }
  return s;
}

// 1 inside [at, end), ramping over `ramp` seconds on each side (0 ramp: a step).
double window(double t, double at, double end, double ramp) {
  if (t < at || t >= end) return 0.0;
  if (ramp <= 0.0) return 1.0;
  return std::min({1.0, (t - at) / ramp, std::isfinite(end) ? (end - t) / ramp : 1.0});
}

}  // namespace

EyeBehaviour::EyeBehaviour(const std::vector<EyeAction>& actions, long frames, double fps,
                           const speech::BehaviourSettings& settings, std::uint64_t seed)
    : fps_(fps), frames_(static_cast<std::size_t>(std::max(0L, frames))) {
  std::vector<const EyeAction*> gaze;
  for (const EyeAction& a : actions) {
    switch (a.kind) {
      case EyeKind::Saccades:
        add_saccades(a, settings, seed);
        break;
      case EyeKind::Blinks:
        add_blinks(a, settings, seed);
        break;
      case EyeKind::Blink:
      case EyeKind::Close:
        add_closure(a, settings.blink);
        break;
      case EyeKind::Look:
      case EyeKind::Pursuit:
        gaze.push_back(&a);
        break;
    }
  }
  if (!gaze.empty()) add_gaze(gaze, settings.saccade);
}

void EyeBehaviour::add_saccades(const EyeAction& a, const speech::BehaviourSettings& settings,
                                std::uint64_t seed) {
  moves_eyes_ = true;
  const auto track = speech::saccade_track(static_cast<long>(frames_.size()), fps_,
                                           styled(settings.saccade, a.style), seed * 3 + 12);
  const bool thinking = a.style == "thinking";
  for (std::size_t k = 0; k < frames_.size(); ++k) {
    const double t = static_cast<double>(k) / fps_;
    if (t < a.at || t >= a.end) continue;
    frames_[k].yaw_deg += track[k].yaw_deg;
    frames_[k].pitch_deg += track[k].pitch_deg;
    if (thinking) {  // eyes drift up and aside while thinking
      const double w = window(t, a.at, a.end, 0.25);
      frames_[k].yaw_deg += 5.0 * w;
      frames_[k].pitch_deg -= 6.0 * w;
    }
  }
}

void EyeBehaviour::add_blinks(const EyeAction& a, const speech::BehaviourSettings& settings,
                              std::uint64_t seed) {
  moves_lids_ = true;
  speech::BlinkSettings blink = settings.blink;
  if (a.rate_per_min > 0) {
    blink.mean_interval_s = 60.0 / a.rate_per_min;
    blink.min_interval_s = std::min(blink.min_interval_s, 0.5 * blink.mean_interval_s);
  }
  const auto track =
      speech::blink_track(static_cast<long>(frames_.size()), fps_, blink, seed * 3 + 11);
  for (std::size_t k = 0; k < frames_.size(); ++k) {
    const double t = static_cast<double>(k) / fps_;
    if (t >= a.at && t < a.end) frames_[k].closure = std::max(track[k], frames_[k].closure);
  }
}

void EyeBehaviour::add_closure(const EyeAction& a, const speech::BlinkSettings& blink) {
  moves_lids_ = true;
  for (std::size_t k = 0; k < frames_.size(); ++k) {
    const double t = static_cast<double>(k) / fps_;
    double c = 0.0;
    if (a.kind == EyeKind::Blink) {
      const double u = t - a.at;
      if (u >= 0 && u < blink.close_s)
        c = smoothstep(u / blink.close_s);
      else if (u >= blink.close_s && u < blink.close_s + blink.hold_s)
        c = 1.0;
      else if (u >= blink.close_s + blink.hold_s && u < blink.close_s + blink.hold_s + blink.open_s)
        c = 1.0 - smoothstep((u - blink.close_s - blink.hold_s) / blink.open_s);
    } else {
      c = a.amount * smoothstep(window(t, a.at, a.end, a.ramp));
    }
    frames_[k].closure = std::max(frames_[k].closure, c);
  }
}

void EyeBehaviour::add_gaze(const std::vector<const EyeAction*>& gaze,
                            const speech::SaccadeSettings& s) {
  moves_eyes_ = moves_head_ = moves_lids_ = true;
  // Where each action takes over from: the previous one's gaze at its start.
  std::vector<Direction> from(gaze.size());
  for (std::size_t i = 1; i < gaze.size(); ++i)
    from[i] = gaze_during(*gaze[i - 1], from[i - 1], gaze[i]->at, s);

  const double follow = 1.0 - std::exp(-1.0 / (fps_ * kHeadLagS));
  Direction head;
  std::size_t current = 0;
  for (std::size_t k = 0; k < frames_.size(); ++k) {
    const double t = static_cast<double>(k) / fps_;
    while (current + 1 < gaze.size() && gaze[current + 1]->at <= t) ++current;
    Direction g;
    if (t >= gaze[current]->at) g = gaze_during(*gaze[current], from[current], t, s);
    // The head takes a share of what lies beyond the eyes' comfortable range, with a lag.
    const double size = std::hypot(g.yaw_deg, g.pitch_deg);
    const double share = size > kHeadFreeDeg ? kHeadShare * (size - kHeadFreeDeg) / size : 0.0;
    head.yaw_deg += follow * (share * g.yaw_deg - head.yaw_deg);
    head.pitch_deg += follow * (share * g.pitch_deg - head.pitch_deg);

    EyeFrame& f = frames_[k];
    const double eye_pitch = g.pitch_deg - head.pitch_deg;
    f.yaw_deg += g.yaw_deg - head.yaw_deg;
    f.pitch_deg += eye_pitch;
    f.head_yaw_deg = head.yaw_deg;
    f.head_pitch_deg = head.pitch_deg;
    f.head_activity = std::clamp(std::hypot(head.yaw_deg, head.pitch_deg), 0.0, 1.0);
    f.lid_irisd = eye_pitch * (eye_pitch > 0 ? kLidPerDegreeDown : kLidPerDegreeUp);
    f.lid_activity = std::clamp(std::abs(eye_pitch), 0.0, 1.0);
  }
}

}  // namespace rostro::script
