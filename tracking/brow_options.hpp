#pragma once
// The brow dots' rule (MPEG-4 4.3, 4.4), TrackerOptions::brows; docs/rules.md measures it on
// and off.

namespace rostro::tracking {

struct BrowOptions {
  // The edge-fitted centre for the mid-brow dots (4.3, 4.4) too. They sit on or just above the
  // eyebrow, a band darker than the skin that the brow's raise slides against the dot: the
  // centroid is pulled toward the band, the edge fit much less (docs/rules.md;
  // tests/tracking/mid_brow_band_test.cpp).
  bool edge_fit_mid_brows = true;
};

}  // namespace rostro::tracking
