#pragma once
// For the mapping tests of a dot hidden for a while: frames fitted one after another, completed
// by the default hierarchy, and how far the hidden dot's FAP then lies from the truth.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "facecore/fapu.hpp"
#include "mapping/fap_solver.hpp"
#include "mapping/hierarchy.hpp"

namespace rostro::test {

// Fits frame_at(i) for i < frames with `solver` (truth_at(i): the FAP id -> value that drove
// it) and returns the largest error of `hidden_fap`, after the hierarchy, over the frames from
// `hidden_from` on. Expects every frame fitted, `seen_fap` within 3 units of its truth before
// the hierarchy and `hidden_fap` written after it.
template <class FrameAt, class TruthAt>
double worst_hidden_error(mapping::FapSolver& solver, const Fapu& fapu, int frames, int hidden_from,
                          int hidden_fap, int seen_fap, FrameAt frame_at, TruthAt truth_at) {
  const mapping::Hierarchy hierarchy = mapping::default_hierarchy();
  double worst = 0;
  for (int i = 0; i < frames; ++i) {
    const std::map<int, double> truth = truth_at(i);
    mapping::FitResult r = solver.fit(frame_at(i));
    EXPECT_TRUE(r.ok);
    EXPECT_NEAR(r.faps.get(seen_fap), truth.at(seen_fap), 3.0) << "frame " << i;
    mapping::apply_hierarchy(hierarchy, fapu, r.faps);
    EXPECT_TRUE(r.faps.has(hidden_fap)) << "frame " << i;
    if (i >= hidden_from && r.faps.has(hidden_fap))
      worst = std::max(worst, std::abs(r.faps.get(hidden_fap) - truth.at(hidden_fap)));
  }
  return worst;
}

}  // namespace rostro::test
