#include "speech/behaviour.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <random>

#include "facecore/data_path.hpp"
#include "facecore/error.hpp"
#include "facecore/json_file.hpp"

namespace rostro::speech {
namespace {

double smoothstep(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * (3.0 - 2.0 * x);
}

// Gamma-distributed intervals (shape k) with a floor: irregular but never machine-gun fast.
double draw_interval(std::mt19937_64& rng, double mean, double min, double shape) {
  const double free_mean = std::max(1e-3, mean - min);
  std::gamma_distribution<double> gamma(shape, free_mean / shape);
  return min + gamma(rng);
}

}  // namespace

BehaviourSettings BehaviourSettings::load(const std::filesystem::path& path) {
  const nlohmann::json j = read_json_file(path, "the behaviour settings");
  BehaviourSettings s;
  try {
    const auto get = [](const nlohmann::json& o, const char* key, auto& value) {
      if (o.contains(key)) value = o.at(key).get<std::decay_t<decltype(value)>>();
    };
    if (j.contains("blink")) {
      const auto& b = j["blink"];
      get(b, "mean_interval_s", s.blink.mean_interval_s);
      get(b, "min_interval_s", s.blink.min_interval_s);
      get(b, "interval_shape", s.blink.interval_shape);
      get(b, "close_s", s.blink.close_s);
      get(b, "hold_s", s.blink.hold_s);
      get(b, "open_s", s.blink.open_s);
      get(b, "closed_top_irisd", s.blink.closed_top_irisd);
      get(b, "closed_bottom_irisd", s.blink.closed_bottom_irisd);
    }
    if (j.contains("saccade")) {
      const auto& a = j["saccade"];
      get(a, "mean_interval_s", s.saccade.mean_interval_s);
      get(a, "min_interval_s", s.saccade.min_interval_s);
      get(a, "mean_amplitude_deg", s.saccade.mean_amplitude_deg);
      get(a, "max_amplitude_deg", s.saccade.max_amplitude_deg);
      get(a, "max_offset_deg", s.saccade.max_offset_deg);
      get(a, "return_probability", s.saccade.return_probability);
      get(a, "duration_base_s", s.saccade.duration_base_s);
      get(a, "duration_per_deg_s", s.saccade.duration_per_deg_s);
    }
    if (j.contains("head")) {
      const auto& h = j["head"];
      get(h, "base_frequency_hz", s.head.base_frequency_hz);
      get(h, "octaves", s.head.octaves);
      get(h, "pitch_deg", s.head.pitch_deg);
      get(h, "yaw_deg", s.head.yaw_deg);
      get(h, "roll_deg", s.head.roll_deg);
    }
    if (j.contains("emotion")) {
      get(j["emotion"], "default_ramp_s", s.default_ramp_s);
      get(j["emotion"], "expression_weight", s.expression_weight);
    }
  } catch (const nlohmann::json::exception& e) {
    throw InputError(where(path.string(), 0, std::string("bad behaviour settings: ") + e.what()));
  }
  if (s.blink.mean_interval_s <= s.blink.min_interval_s * 0.5 || s.blink.interval_shape <= 0 ||
      s.saccade.mean_interval_s <= 0 || s.head.octaves < 1 || s.head.octaves > 8 ||
      s.expression_weight < 0 || s.expression_weight > 1)
    throw InputError(where(path.string(), 0, "behaviour settings out of range"));
  return s;
}

BehaviourSettings BehaviourSettings::load_default() {
  return load(data_file("speech/behaviour.json"));
}

std::vector<double> blink_track(long frames, double fps, const BlinkSettings& s,
                                std::uint64_t seed) {
  std::vector<double> out(static_cast<std::size_t>(std::max(0L, frames)), 0.0);
  std::mt19937_64 rng(seed);
  const double end = static_cast<double>(frames) / fps;
  // The first blink comes after a partial interval, so clips do not all open with a blink.
  std::uniform_real_distribution<double> first(0.3, 1.0);
  double t0 =
      first(rng) * draw_interval(rng, s.mean_interval_s, s.min_interval_s, s.interval_shape);
  while (t0 < end) {
    const double t1 = t0 + s.close_s, t2 = t1 + s.hold_s, t3 = t2 + s.open_s;
    const long k0 = std::max(0L, static_cast<long>(std::floor(t0 * fps)));
    const long k3 = std::min(frames - 1, static_cast<long>(std::ceil(t3 * fps)));
    for (long k = k0; k <= k3; ++k) {
      const double t = static_cast<double>(k) / fps;
      double c = 0.0;
      if (t >= t0 && t < t1)
        c = smoothstep((t - t0) / s.close_s);
      else if (t >= t1 && t < t2)
        c = 1.0;
      else if (t >= t2 && t < t3)
        c = 1.0 - smoothstep((t - t2) / s.open_s);
      auto& v = out[static_cast<std::size_t>(k)];
      v = std::max(v, c);
    }
    // A blink is always visible: the frame nearest the closed phase shows it shut.
    const long mid = std::lround((t1 + t2) / 2 * fps);
    if (mid >= 0 && mid < frames) out[static_cast<std::size_t>(mid)] = 1.0;
    t0 = t3 + draw_interval(rng, s.mean_interval_s, s.min_interval_s, s.interval_shape);
  }
  return out;
}

std::vector<Gaze> saccade_track(long frames, double fps, const SaccadeSettings& s,
                                std::uint64_t seed) {
  std::vector<Gaze> out(static_cast<std::size_t>(std::max(0L, frames)));
  std::mt19937_64 rng(seed);
  std::exponential_distribution<double> amplitude(1.0 / s.mean_amplitude_deg);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Gaze from, to;
  double start = -1.0, duration = 1.0;  // no saccade yet: looking at the listener
  const auto plan_next = [&](double t) {
    from = to;
    if (unit(rng) < s.return_probability) {
      to = Gaze{};  // back to the listener
    } else {
      const double a = std::min(amplitude(rng), s.max_amplitude_deg);
      const double angle = 2.0 * std::numbers::pi * unit(rng);
      to.yaw_deg =
          std::clamp(from.yaw_deg + a * std::cos(angle), -s.max_offset_deg, s.max_offset_deg);
      to.pitch_deg = std::clamp(from.pitch_deg + 0.6 * a * std::sin(angle), -s.max_offset_deg,
                                s.max_offset_deg);
    }
    const double moved = std::hypot(to.yaw_deg - from.yaw_deg, to.pitch_deg - from.pitch_deg);
    start = t;
    duration = s.duration_base_s + s.duration_per_deg_s * moved;  // main-sequence duration
  };
  double next = draw_interval(rng, s.mean_interval_s, s.min_interval_s, 2.0);
  for (long k = 0; k < frames; ++k) {
    const double t = static_cast<double>(k) / fps;
    while (t >= next) {
      plan_next(next);
      next = start + duration + draw_interval(rng, s.mean_interval_s, s.min_interval_s, 2.0);
    }
    const double x = start < 0.0 ? 1.0 : smoothstep((t - start) / duration);
    out[static_cast<std::size_t>(k)] = {from.yaw_deg + x * (to.yaw_deg - from.yaw_deg),
                                        from.pitch_deg + x * (to.pitch_deg - from.pitch_deg)};
  }
  return out;
}

GradientNoise::GradientNoise(std::uint64_t seed) : gradients_(256) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> g(-1.0, 1.0);
  for (auto& v : gradients_) v = g(rng);
}

double GradientNoise::operator()(double x) const {
  const double f = std::floor(x);
  const double u = x - f;
  const auto i = static_cast<long long>(f);
  const auto grad = [&](long long j) {
    return gradients_[static_cast<std::size_t>(((j % 256) + 256) % 256)];
  };
  const double a = grad(i) * u;
  const double b = grad(i + 1) * (u - 1.0);
  const double fade = u * u * u * (u * (u * 6.0 - 15.0) + 10.0);
  return 2.0 * (a + fade * (b - a));  // raw range is about [-0.5, 0.5]
}

std::vector<HeadPose> head_track(long frames, double fps, const HeadSettings& s,
                                 std::uint64_t seed) {
  std::vector<HeadPose> out(static_cast<std::size_t>(std::max(0L, frames)));
  const GradientNoise pitch(seed), yaw(seed + 1), roll(seed + 2);
  const auto fractal = [&](const GradientNoise& n, double t, double offset) {
    double sum = 0.0, amp = 1.0, norm = 0.0, freq = s.base_frequency_hz;
    for (int o = 0; o < s.octaves; ++o) {
      sum += amp * n(t * freq + offset);
      norm += amp;
      amp *= 0.5;
      freq *= 2.0;
    }
    return sum / norm;
  };
  for (long k = 0; k < frames; ++k) {
    const double t = static_cast<double>(k) / fps;
    // Offsets keep time 0 off the lattice, where gradient noise is exactly zero.
    out[static_cast<std::size_t>(k)] = {s.pitch_deg * fractal(pitch, t, 0.37),
                                        s.yaw_deg * fractal(yaw, t, 0.61),
                                        s.roll_deg * fractal(roll, t, 0.13)};
  }
  return out;
}

}  // namespace rostro::speech
