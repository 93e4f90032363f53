#pragma once
// Dynamic time warping between two feature sequences, in linear time and memory: the path
// is found on sequences halved again and again, then refined at each finer level inside a
// band around the coarser path (the FastDTW scheme of Salvador and Chan, 2007).

#include <utility>
#include <vector>

#include "speech/mfcc.hpp"

namespace rostro::speech {

struct WarpPath {
  // (frame of a, frame of b), from (0, 0) to (a.frames-1, b.frames-1), each step moving one
  // frame in a, in b, or in both.
  std::vector<std::pair<int, int>> steps;
  // The path's cost over its weight (a.frames + b.frames): the mean distance between
  // matched frames, with the step penalties.
  double mean_cost = 0.0;
};

struct WarpOptions {
  // How many frames the refined path may stray from the projected coarser one.
  int radius = 24;
  // Added to every step that advances one sequence alone. Without it the path is free to
  // stall on one frame of a and sweep through many of b wherever that is a little cheaper,
  // squeezing a phoneme to nothing; with it a stall must pay for itself (docs/speech.md).
  double step_penalty = 3.0;
};

// Both sequences need at least one frame and the same dims.
WarpPath warp(const Features& a, const Features& b, const WarpOptions& options = {});

// Euclidean distance between frame i of a and frame j of b.
float frame_distance(const Features& a, int i, const Features& b, int j);

}  // namespace rostro::speech
