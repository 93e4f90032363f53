#pragma once
// Animation rules, part 4: sampling the keys at frame times. Frame k is audio time k / fps;
// its mouth is a linear cross-fade between the keys around that instant (seed003 Fig 7),
// computed in absolute time: no per-interval frame counts, so no drift and no division by
// a zero-frame interval. The face stays neutral until the first key (mid-silence).

#include <vector>

#include "speech/coarticulation.hpp"
#include "speech/phoneme.hpp"

namespace rostro::speech {

// value = (1 - weight) x shape(from) + weight x shape(to); key index -1 = neutral.
struct FrameBlend {
  int from = -1;
  int to = -1;
  double weight = 0.0;
};

// Frame count for an audio duration: every frame whose time k / fps lies in [0, duration).
long frame_count_for(double duration_s, double fps);

std::vector<FrameBlend> sample_keys(const std::vector<Key>& keys, long frame_count, double fps);

// Bilabial guarantee: for every phoneme that closes the lips, at least one frame within
// half a frame of it shows a closing key at full weight. When the cross-fade alone does
// not give one (a /p/ shorter than a frame, or a closure key between two frames), the frame
// nearest the closure key is set to that key. Returns how many frames were set.
int ensure_bilabial_closures(std::vector<FrameBlend>& frames, const std::vector<Key>& keys,
                             const std::vector<Phoneme>& phonemes, double fps);

// How much of frame's mouth comes from keys that close the lips (0..1).
double closure_weight(const FrameBlend& frame, const std::vector<Key>& keys,
                      const std::vector<Phoneme>& phonemes);

}  // namespace rostro::speech
