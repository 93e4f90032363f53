#include "speech/key_sampler.hpp"

#include <algorithm>
#include <cmath>

namespace rostro::speech {
namespace {

bool closes(const Key& key, const std::vector<Phoneme>& p) {
  return key.consonant >= 0 && key.kind != KeyKind::Neutral && key.kind != KeyKind::Vowel &&
         p[static_cast<std::size_t>(key.consonant)].closes_lips;
}

}  // namespace

long frame_count_for(double duration_s, double fps) {
  if (!(duration_s > 0.0) || !(fps > 0.0)) return 0;
  // ceil, with a guard so that 2.0 s x 25 fps is 50 frames and not 51 through rounding.
  return static_cast<long>(std::ceil(duration_s * fps - 1e-9));
}

std::vector<FrameBlend> sample_keys(const std::vector<Key>& keys, long frame_count, double fps) {
  std::vector<FrameBlend> out(static_cast<std::size_t>(std::max(0L, frame_count)));
  const int n = static_cast<int>(keys.size());
  int last = -1;  // the last key at or before the frame time; frames only move forward
  for (long k = 0; k < frame_count; ++k) {
    const double t = static_cast<double>(k) / fps;  // absolute time, never accumulated
    while (last + 1 < n && keys[static_cast<std::size_t>(last + 1)].time_s <= t) ++last;
    FrameBlend& f = out[static_cast<std::size_t>(k)];
    if (last < 0) {
      f = {-1, n > 0 ? 0 : -1, 0.0};  // before the first key: the neutral face
      if (n > 0 && keys[0].kind != KeyKind::Neutral) {
        // An utterance starting mid-word: fade in from neutral at time 0.
        f.weight = keys[0].time_s > 0.0 ? t / keys[0].time_s : 1.0;
      }
    } else if (last + 1 >= n) {
      f = {last, last, 0.0};
    } else {
      const double a = keys[static_cast<std::size_t>(last)].time_s;
      const double b = keys[static_cast<std::size_t>(last + 1)].time_s;  // b > t >= a
      f = {last, last + 1, (t - a) / (b - a)};
    }
  }
  return out;
}

double closure_weight(const FrameBlend& f, const std::vector<Key>& keys,
                      const std::vector<Phoneme>& p) {
  double c = 0.0;
  if (f.from >= 0 && closes(keys[static_cast<std::size_t>(f.from)], p)) c += 1.0 - f.weight;
  if (f.to >= 0 && closes(keys[static_cast<std::size_t>(f.to)], p)) c += f.weight;
  return c;
}

int ensure_bilabial_closures(std::vector<FrameBlend>& frames, const std::vector<Key>& keys,
                             const std::vector<Phoneme>& p, double fps) {
  int forced = 0;
  const long n = static_cast<long>(frames.size());
  if (n == 0) return 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!p[i].closes_lips) continue;
    const double half = 0.5 / fps;
    const long k0 = std::max(0L, static_cast<long>(std::ceil((p[i].start_s - half) * fps)));
    const long k1 = std::min(n - 1, static_cast<long>(std::floor((p[i].end_s + half) * fps)));
    bool closed = false;
    for (long k = k0; k <= k1 && !closed; ++k)
      closed = closure_weight(frames[static_cast<std::size_t>(k)], keys, p) >= 1.0 - 1e-9;
    if (closed) continue;
    // The closing key of this phoneme nearest its centre.
    int best = -1;
    const double mid = 0.5 * (p[i].start_s + p[i].end_s);
    for (std::size_t j = 0; j < keys.size(); ++j)
      if (keys[j].consonant == static_cast<int>(i) && closes(keys[j], p) &&
          (best < 0 || std::abs(keys[j].time_s - mid) <
                           std::abs(keys[static_cast<std::size_t>(best)].time_s - mid)))
        best = static_cast<int>(j);
    if (best < 0) continue;
    long k = std::lround(keys[static_cast<std::size_t>(best)].time_s * fps);
    k = std::clamp(k, std::max(0L, k0), std::max(k0, k1));
    k = std::min(k, n - 1);
    frames[static_cast<std::size_t>(k)] = {best, best, 0.0};
    ++forced;
  }
  return forced;
}

}  // namespace rostro::speech
