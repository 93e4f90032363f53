#pragma once
// Follows the layout's markers through a take, frame by frame.
//
// First frame: every dot and tag is detected and identified (identify.hpp), or the markers
// start where a file of starting positions puts them. Then, per frame:
//  1. dots and tag corners move by pyramidal Lucas-Kanade from the previous frame, checked
//     forward-backward. The pyramid covers only the region the markers occupy (plus room for
//     a frame's motion) and its derivatives are computed only where LK reads them
//     (lk_pyramid.hpp); colour frames are converted to grey only there and in the windows
//     searched;
//  2. each dot is snapped to its measured centre (dot_detector.hpp), so errors never add up;
//     a dot whose contrast, size, shape or surroundings fail the checks turns invalid, and so
//     does one that moved unlike its neighbours or landed on another's spot, and an eye dot
//     that grew (merged with the pupil or the other lid's dot: their centre is neither's) or,
//     a lid dot, turned twice as tall as wide (merged with the pupil, at a dot's size); an
//     inner brow dot merged with the eyebrow's end is placed by its ink's darker core;
//  3. tags are re-detected in a small window around where LK puts their corners every few
//     frames (and whenever a corner fails LK's round trip or the square changes size); in
//     between, LK on their corners follows them (tags are rigid);
//  4. an invalid marker is looked for near where its valid neighbours say it should be
//     (an affine fit of the neighbours' start positions to their current ones; a lid dot is
//     carried instead from where it was last seen with its neighbours' motion since, as the
//     eyes sit at another depth; any dot so in the frame it is lost in), among every dot there,
//     nearest first, and comes back with its own identity; it is never guessed while unseen. A lid
//     dot is only accepted between its eye's corner line and not far beyond its start distance from
//     it. The lower lip's dots are looked for together, below the upper lip, and found again
//     only where their shape fits (TrackerOptions::lower_lip_together).

#include <map>
#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "tracking/apriltag_detector.hpp"
#include "tracking/dot_detector.hpp"
#include "tracking/layout.hpp"
#include "tracking/tracked_frame.hpp"

namespace rostro::tracking {

struct TrackerOptions {
  DotOptions dots;
  AprilTagOptions tags;  // for the first frame (whole image)
  // The pixel-valued options below hold for dots this wide; with larger dots measured at the
  // start (a larger image of the face) they grow in proportion (the LK window with the square
  // root of it).
  double reference_dot_px = 8;
  // The edge-fitted centre (DotOptions::edge_fit) for the lid and outer eye-corner dots, where
  // the centroid is pulled toward the slit and the lashes by 0.4-0.6 px (the inner corners: see
  // inner_corners_raise_share); elsewhere the centroid
  // (false), as the edge fit moved the inner brow dots at 640x480 (5 px dots against the brow's
  // fold) and flipped the identity of the mouth clip's dots.
  bool edge_fit_elsewhere = false;
  // The edge-fitted centre for the mid-brow dots (4.3, 4.4) too. They sit on the eyebrow, a
  // band lighter than the ink that the brow's raise moves against the dot: the centroid was
  // pulled toward the band's larger side (Xface fear at 640x480: 0.3 px down, spread 0.1 px;
  // edge-fitted 0.1 px and 0.03; raise_m_eyebrow 5.2-5.8 -> 2.1 % of range).
  bool edge_fit_mid_brows = true;
  // The inner eye-corner dots (3.8, 3.11) sit where the eye slit's corner runs out in a thin
  // dark line. At 1280x720 the line joins the dot's blob at half its contrast and the blob
  // fails the roundness check; DotOptions::raise_share_for_roundness measures it higher up
  // instead (without it the inner corners were lost in 204 of 225 frames of the closed loop's
  // still head at 1280x720). They are not edge-fitted: the edge fit's rays there run along the
  // line and the lashes (centre: inner_corners_symmetric_centre).
  bool inner_corners_raise_share = true;
  // The inner corners' centre where the blob best overlaps its own point reflection
  // (DotOptions::symmetric_centre) rather than the blob's centroid. The slit's corner, which
  // grows as the eye widens, pulled the centroid toward the eye: the closed loop's Xface fear
  // against the still head, 0.30 px further in x at 640x480 and 0.45 at 1280x720 (the head's
  // yaw took it up: 8.5 % of range at 640x480); symmetric, 0.02-0.04 px.
  bool inner_corners_symmetric_centre = true;
  // The longest the inner eye-corner dots' blob may be (long over short axis) when the dots
  // are at least reference_dot_px wide; smaller dots keep DotOptions::max_elongation (3). The
  // inner corner sits in the hollow beside the nose, seen steeply when the head turns: at
  // 1280x720 and yaw -16 degrees it is 3.15 times as long as wide, and rejected it was found
  // again on the lash line 10 px away (closed loop, turns: close_t_l_eyelid 18.9 % of range,
  // 6.6 % at 4). At 640x480 a blob that long is the dot merged with the slit's corner line
  // (joy with head turns: 57 -> 124 % at 4).
  double inner_corner_max_elongation_large = 4;
  int lk_window = 13;                 // pixels
  int lk_levels = 2;                  // pyramid levels above the image: motion up to ~25 px/frame
  double region_margin_px = 24;       // LK region: the markers' box + this + the top window
  double max_fb_error = 1.0;          // pixels, forward-backward round trip
  double max_snap = 2.5;              // pixels between LK's answer and the dot's centre
  double min_contrast_ratio = 0.4;    // of the dot's contrast at identification
  double tag_margin = 0.3;            // tag search window: expected box + this x tag size
  double tag_decimate_above_px = 48;  // tags wider than this are searched at half resolution
  int tag_redetect_every = 4;         // frames; in between LK follows the tags' corners
  double search_fraction = 0.45;      // re-acquisition radius, fraction of the nearest spacing
  // Eye dots (lids, corners): the farthest a followed dot's measured centre may lie from where LK
  // moved it, pixels at reference_dot_px (scaled with the dots' size, as max_snap). The two
  // agree to 0.25 px in 90-99 % of frames (closed loop, both sizes); a centre farther off is
  // the dot measured together with a dark neighbour it touches for the frame: an inner
  // eye-corner dot seen edge-on with the eye slit's corner wedge (turns at 640x480: 2.35 px into
  // the eye, then followed there 2-2.5 px off for 18 frames), a lid dot with the iris. Such a dot
  // is reported lost and looked for again. Large values: max_snap alone.
  double max_eye_snap = 1.5;
  // A lost lid dot is carried from where it was last seen, and found again only this far
  // (fraction of its spacing) to the side of there, along its eye's corner-to-corner line.
  double lid_sideways_fraction = 0.25;
  // A lid dot is kept (while both eye corners are followed) and found again only on its own
  // side of its eye's corner line, or this fraction of its spacing past it, ...
  double lid_overshoot_fraction = 0.15;
  double lid_reach = 1.7;  // and at most this many times its distance from the line at the start
  // How far a dot's frame-to-frame motion may differ from its neighbours' (the larger of a
  // fraction of its spacing at the start, and pixels): expressions, not jumps to another dot.
  double max_relative_motion = 0.35;
  double max_relative_motion_px = 4;
  // The lower lip's dots (MPEG-4 8.2, 8.7, 8.8) when the mouth opens or shuts within a frame
  // (Xface joy: the lower lip 17-23 px in a frame at 1280x720, past LK's reach and past
  // search_fraction). Lost ones are looked for together, not one by one: in the frame of the
  // upper lip's and the corners' dots (a similarity from their start positions), in a strip
  // from lower_lip_up above to lower_lip_down below each dot's start place and
  // lower_lip_sideways to either side (fractions of the lower lip's spacing: the closed loop's
  // drives reach 1.3-2.1 down and 0.4 sideways), and taken only where one shift puts at least
  // two of the three, followed or found, each on a dot within lower_lip_shape of it (the three
  // keep their shape to 0.37). One at a time a dropped dot was found again on the open mouth's
  // dark corner or on its neighbour's dot, up to 30 px off (joy with head turns at 1280x720:
  // raise_b_lip 33 % of range). The lower lip's dots are also no neighbours in the other dots'
  // check that a dot moves as its neighbours do: the lower lip moves unlike them. false: one by
  // one, as any dot.
  bool lower_lip_together = true;
  double lower_lip_up = 0.5;
  double lower_lip_down = 2.5;
  double lower_lip_sideways = 0.6;
  double lower_lip_shape = 0.4;
  // Eye dots (lids, corners): largest size of a followed dot over its size in the last
  // frames. A larger blob is the dot merged with a dark neighbour (the pupil, the other lid's
  // dot in a blink), whose centre is neither's: the dot is reported lost. The same for a dot
  // found again after a loss, over the larger of its size when last seen and at the start
  // (scaled as the face). Other dots keep the looser 0.5-2x of their start size.
  double max_dot_growth = 1.15;
  double max_dot_growth_found = 1.2;
  // ... except that an eye dot last seen edge-on (at least edge_on_elongation long over short)
  // and lost for fewer frames than this is held to its size when last seen, not the larger of
  // that and its start size: an inner eye-corner dot seen edge-on under a head turn (a third of
  // its start width) merges with the eye slit's dark corner beside it into a blob about its
  // start size, whose centre lies 2-4 px into the eye (closed loop, Xface joy with head turns,
  // at 640x480 and 1280x720). Not after a round dot: one shrunk for a while (half covered) comes
  // back at its start size (suite, occlusion: 6 -> 29 lost frames). 0: the start size always.
  int eye_size_memory_frames = 25;
  double edge_on_elongation = 2;
  // Lid dots: largest long / short axis of the blob. A lid dot merged with the pupil (the
  // upper lid lowered over it in a smile, the head pitched) keeps about a dot's area, so the
  // growth check above passes it, but is a tall blob: 1.6-2.8 against at most 1.72 for a lone
  // lid dot under yaw +-25 and pitch +-15 (closed loop, 640x480 and 1280x720).
  double max_lid_elongation = 1.8;
  // Lid dots: largest median contrast of the ring just outside the blob, as a share of its own
  // (Dot::surround; DotOptions::max_surround, 0.55, holds for every dot). A lower-lid dot merged
  // with the pupil above it (the lid raised in a smile, the head pitched) is measured high up,
  // its centre 2-3 px into the eye, inside the dark iris: 0.45-0.55 there, against at most 0.45
  // for a lone lid dot at 640x480 (7 frames in 2356 above it at 1280x720; closed loop clips).
  double max_lid_surround = 0.45;
  // An inner brow dot (4.1, 4.2) sits at the eyebrow's end. Where the eyebrow (nearly as dark
  // as the ink) touches it, the two merge at every share of the dot's contrast and the blob's
  // centre, and its edge, lie up to 2 px out along the eyebrow (closed loop, head turns at
  // 640x480: squeeze_eyebrow 14 % of range). Such a blob (measured above half its contrast, and
  // still not at 0.9, or long or ragged there) does not place the dot by its centre
  // (tests/tracking/brow_merge_test.cpp). false: the blob's centre.
  bool hold_merged_inner_brows = true;
  // Such a dot is placed at the centre of its ink's core (tracking/ink_core.hpp): the pixels within
  // this share of its contrast of the darkest within 0.7 of its width of where LK moved it (of the
  // merged blob's centre when found again after a loss, or at the start). The ink is darker than
  // the eyebrow's end. Held where LK moved it, the dot drifted: LK weighs the eyebrow in its
  // window, and each frame's pull added to the last (closed loop, turns at 640x480: 0.2 -> 0.9 px
  // off over 55 frames, squeeze_r_eyebrow 8.5 % of range, about 3 % with the core); a dot found
  // again on the merged blob was held 1.7 px off. 0: where LK moved it.
  double inner_brow_core_tolerance = 0.08;
  int min_identified = 3;  // markers needed to start tracking
  // Threads the followed dots' centres are measured on each frame (0: the machine's cores;
  // OpenCV's cv::setNumThreads caps them). Any count gives the same tracks: each dot is
  // measured on its own, then all are judged and applied in layout order.
  int threads = 0;

  // Throws InputError naming the first option out of range (lk_window <= 0, max_dot_growth
  // < 1, ...), this struct's or its DotOptions'. MarkerTracker's constructor calls it.
  void validate() const;
};

// Sets one field of `options` from "NAME=VALUE", NAME a field's name as above (a DotOptions
// field as "dots.NAME"), e.g. "max_dot_growth=1.3" or "lower_lip_together=false": for
// `rostro eval suite --tracker-option`. Throws InputError for an unknown name or a bad value.
void set_tracker_option(TrackerOptions& options, const std::string& assignment);

// Why a marker is not valid this frame: the rule that dropped it, kept while it stays lost, or
// that it was never identified. `rostro eval suite` counts each per clip.
enum class LostReason {
  None,           // valid
  Unidentified,   // not identified (or not at its start position) when tracking started
  RoundTrip,      // LK's forward-backward round trip failed (max_fb_error)
  NoDot,          // no dot passing DotOptions' checks within max_snap of where LK moved it
  Snap,           // its dot's centre farther than max_snap from where LK moved it
  EyeSnap,        // an eye dot's centre farther than max_eye_snap from there
  LidElongation,  // a lid dot's blob longer than max_lid_elongation
  LidSurround,    // a lid dot's ring darker than max_lid_surround
  Contrast,       // below min_contrast_ratio of its contrast at the start
  Shrunk,         // under half its size at the start
  Growth,         // an eye dot grown past max_dot_growth(_found); another over twice its start size
  Jump,           // moved unlike its neighbours (max_relative_motion, max_relative_motion_px)
  Coincident,     // on the spot of another dot (both are dropped)
  LidBand,        // a lid dot off its band (lid_overshoot_fraction, lid_reach)
  TagLost,        // a tag not detected again near where LK moved its corners
};
inline constexpr int kLostReasonCount = static_cast<int>(LostReason::TagLost) + 1;
// A few words: "round trip", "lid band", ...
const char* to_string(LostReason reason);

// One marker's state as the overlay draws it.
struct MarkerState {
  const MarkerSpec* spec = nullptr;
  bool valid = false;
  LostReason lost_reason = LostReason::Unidentified;  // None while valid
  cv::Point2d position;
  std::array<cv::Point2d, 4> corners{};  // tags only
  double quality = 0;
  int lost_frames = 0;  // frames since it was last valid
};

class MarkerTracker {
 public:
  MarkerTracker(MarkerLayout layout, TrackerOptions options = {});
  ~MarkerTracker();

  // Start from these positions (layout id -> pixels) instead of identifying automatically.
  void set_start_positions(const std::map<std::string, cv::Point2d>& positions);

  // `image`: 8-bit grey or BGR. Every layout marker appears in the result, in layout order.
  TrackedFrame track(const cv::Mat& image, long frame, double time_s);

  bool started() const;
  const std::vector<MarkerState>& states() const;
  const MarkerLayout& layout() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rostro::tracking
