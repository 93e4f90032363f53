#pragma once
// Round dot markers: finding them in a whole image or a window, and measuring one dot's
// centre to a fraction of a pixel.
//
// Finding: the local background (a box mean a few dot-widths wide) minus the image (dark
// dots) or the reverse (bright dots) is smoothed, and each local maximum of it is measured
// as below and kept when it passes the size, contrast and roundness checks (thresholded blobs
// would merge a dot with the shadow beside it: the nose, the lips, the chin); a dot touching a
// darker feature is measured at a higher share of its contrast, where it stands alone. Centre: the
// contrast-weighted centroid over the blob, then the centre of an ellipse fitted to sub-pixel
// edge points along 32 rays, each where the ray's profile crosses halfway between the ink and
// the level just outside (the skin's, from a plane fitted to the rays that see skin, or a
// darker feature's own where one lies flat against the dot); rays with no clean step are
// dropped. The centroid alone is pulled toward a shading gradient's dark side and toward a
// darker feature beside the dot (the eye slit, the iris, the mouth, a brow's shadow); the
// edge fit is not, and stands in only where enough of the rim gives a clean edge.

#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "tracking/layout.hpp"

namespace rostro::tracking {

struct DotOptions {
  DotPolarity polarity = DotPolarity::Dark;
  double min_diameter_px = 4;
  double max_diameter_px = 30;
  double min_contrast = 20;  // grey levels between a dot's core and its surroundings
  // Blob area / area of the smallest ellipse of its own orientation and aspect holding it.
  double min_roundness = 0.55;
  double min_roundness_merged = 0.4;  // the same for a dot touching a darker feature
  // Long / short axis: a round dot on skin turned up to ~70 degrees from the camera (the chin
  // seen from the front).
  double max_elongation = 3;
  // Largest median contrast of the ring just outside a dot, as a share of the dot's: the
  // pupil, ringed by the dark iris, is as round and dark as a dot but fails this.
  double max_surround = 0.55;
  // Centre from the ellipse through the dot's edge (see above) where its surroundings are
  // uneven; false: the contrast-weighted centroid alone.
  bool edge_fit = true;
  // A blob of the right size that fails the roundness check at its share of the contrast is
  // measured again at the higher shares, and kept at the first that is round enough; false:
  // rejected. A thin dark line running into a dot (the eye slit's corner beside an inner
  // eye-corner dot at 1280x720) adds few pixels but reaches far, so the blob at half is not
  // round; a share up it weighs less.
  bool raise_share_for_roundness = false;
  // Centre where the dot's contrast best overlaps its own point reflection (the largest sum
  // of min(c(p), c(2m - p)) over the pixels the centroid weighs: the blob and its rim) instead
  // of the centroid: a dark feature running into the dot from one side (the eye slit's corner
  // at an inner eye-corner dot) reflects onto skin and adds nothing, where it pulls the
  // centroid toward itself the more the longer and wider it grows (Xface fear at 1280x720:
  // 0.45 px more toward the eye than on a still face; symmetric, 0.04). The blob, size and
  // checks are as without it; the edge fit, if on, starts from here.
  bool symmetric_centre = false;

  // Throws InputError naming the first option out of range (a size or contrast below 0, a
  // roundness outside 0..1, ...).
  void validate() const;
};

struct Dot {
  cv::Point2d center;
  double diameter = 0;  // equivalent-area diameter, pixels
  double contrast = 0;  // grey levels, positive for the expected polarity
  // Median contrast of a ring just outside the dot, as a share of `contrast`: near 0 for a
  // dot on skin, high for a dark disc inside a darker ring (the pupil in the iris).
  double surround = 0;
  // Long over short axis of the blob it was measured on: a lid dot merged with the pupil
  // below or above it is a blob twice as tall as wide.
  double elongation = 1;
  // The share of its contrast the blob was measured at (half on plain skin; higher where it
  // merged with a darker feature at half), and the blob's roundness there (as
  // DotOptions::min_roundness): a dot merged with a feature nearly as dark as its ink (an inner
  // brow dot against the eyebrow's end) is measured high up and is long or ragged even there.
  double share = 0.5;
  double roundness = 1;
};

// Every dot in `gray` (8-bit, one channel) within `roi` (all of it when empty), in
// full-image pixels, strongest first.
std::vector<Dot> detect_dots(const cv::Mat& gray, const DotOptions& options, cv::Rect roi = {});

// The dot nearest `guess` measured precisely, searched within `radius` pixels of it; nullopt
// when there is no dot there that passes the options' checks.
std::optional<Dot> refine_dot(const cv::Mat& gray, cv::Point2d guess, double radius,
                              const DotOptions& options);

// Every dot whose core lies within `radius` of `guess` (up to `most`), nearest first: for
// looking a lost marker up beside dark features that are no dots (the pupil, an eyebrow),
// where the strongest point near the guess is not the marker. Peaks weaker than
// `least_contrast` (grey levels) are not measured.
std::vector<Dot> dots_near(const cv::Mat& gray, cv::Point2d guess, double radius,
                           const DotOptions& options, int most = 4, double least_contrast = 0);

}  // namespace rostro::tracking
