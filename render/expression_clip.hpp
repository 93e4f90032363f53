#pragma once
// Short demonstration clips built from the high-level FAPs: neutral easing into an
// expression (FAP 2) and holding it, for `rostro play --expression joy`.

#include "facecore/fap_frame.hpp"

namespace rostro::render {

struct ClipTiming {
  double fps = 25.0;
  double hold_neutral_s = 0.4;  // neutral before the change
  double ramp_s = 1.0;          // smooth (cosine) ease from 0 to full intensity
  double hold_s = 1.0;          // full expression at the end
};

// Frames carrying FAP 2 with expression_select `select` (1..6) and intensity rising from 0 to
// `intensity` (0..63). Throws rostro::InputError for a bad select, intensity or timing.
FapStream expression_clip(int select, int intensity, const ClipTiming& timing = {});

}  // namespace rostro::render
