#pragma once
// The lower lip's dots found again together (LowerLipOptions::together, part of
// TrackerOptions), in rostro::tracking::internal: MarkerTracker hands over the mouth's dots and
// two callbacks (finding dots in a window, checking one found) and takes back the dots found.
//
// The lower lip's dots, lost together when the mouth opens or shuts within a frame, are found
// again together: in the mouth's frame (a similarity taking the followed upper-lip and corner
// dots from their start positions to their current ones) the lower lip moves, from its start
// place, as one piece and chiefly down (opening) or back up, so a shift shared by its dots (one
// followed dot's, or one candidate's) must put at least two of them (followed or found) each on
// a dot. A lone dark blob (the open mouth's corner, a gap by the teeth) or a sibling's dot (the
// triangle then fits nowhere) is not taken. The tracker hands over only the dots it saw when
// tracking started: a start place the identification guessed is no shape to match.

#include <cstddef>
#include <functional>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "facecore/feature_point.hpp"
#include "tracking/dot_detector.hpp"

namespace rostro::tracking {

// The lower lip's rules, TrackerOptions::lower_lip.
struct LowerLipOptions {
  // The lower lip's dots (MPEG-4 8.2, 8.7, 8.8) when the mouth opens or shuts within a frame
  // (Xface joy: the lower lip 17-23 px in a frame at 1280x720, past LK's reach and past
  // TrackerOptions::search_fraction). Lost ones are looked for together, not one by one: in the
  // frame of the upper lip's and the corners' dots (a similarity from their start positions), in a
  // strip from `up` above to `down` below each dot's start place and `sideways` to either side
  // (fractions of the lower lip's spacing: the closed loop's drives reach 1.3-2.1 down and 0.4
  // sideways), and taken only where one shift puts at least two of the three, followed or found,
  // each on a dot within `shape` of it (the three keep their shape to 0.37). One at a time a
  // dropped dot was found again on the open mouth's dark corner or on its neighbour's dot, tens of
  // pixels off (docs/rules.md measures it on and off). The lower lip's dots are
  // also no neighbours in the other dots' check that a dot moves as its neighbours do: the lower
  // lip moves unlike them. false: one by one, as any dot.
  bool together = true;
  // The jaw's dots (the lower lip's and the chin's, MPEG-4 2.1 and 2.10-2.14) judged and placed
  // by one another: a lower-lip dot's check that it moves as its neighbours do takes the jaw's
  // dots as its neighbours (while three of them are followed), a lost jaw dot is looked for
  // where the face's fit puts it moved as the nearest followed jaw dot has moved from where
  // the fit puts that one, and the jaw's dots are looked for after the others. Among the upper
  // lip's and the corners' dots, which a jaw opening 20 px in a frame hardly moves, the middle
  // lower-lip dot came out as having jumped; the chin, hidden for 14 frames, was looked for
  // where the face's fit (which follows the skull) put it as if the jaw were shut, on the
  // lower lip's dot, and took it (Xface joy with head turns, 1280x720). false: judged by its
  // nearest neighbours, placed by the face's fit, as any dot.
  bool with_the_jaw = true;
  double up = 0.5;
  double down = 2.5;
  double sideways = 0.6;
  double shape = 0.4;

  // Throws InputError naming the first option out of range ("LowerLipOptions::...").
  void validate() const;
};

namespace internal {

// MPEG-4 8.2, 8.7, 8.8: the outer lower lip's dots.
bool at_lower_lip(const FeaturePointId& fp);
// MPEG-4 8.1 and 8.3-8.6: the upper lip's and the mouth corners' dots.
bool at_upper_lip_or_corner(const FeaturePointId& fp);

// One of the lower lip's dots (not a tag) as the tracker has it this frame.
struct LowerLipDot {
  std::size_t marker = 0;  // the tracker's index, handed back to the callbacks and in the result
  cv::Point2d start;       // where it was at the start of tracking
  double spacing = 0;      // nearest other marker at the start, pixels
  bool followed = false;   // valid this frame
  cv::Point2d now;         // where it is, when followed
  bool predicted = false;  // lost and given a place to look for it (searched only then)
};

// A dot (not a tag) followed this frame: a dot found on one is its, not the lower lip's.
struct FollowedDot {
  std::size_t marker = 0;
  cv::Point2d now;
  double spacing = 0;  // nearest other marker at the start, pixels
};

struct LowerLipScene {
  std::vector<LowerLipDot> lower_lip;  // the tracker's order
  // The followed upper-lip and corner dots (at_upper_lip_or_corner), the tracker's order.
  std::vector<cv::Point2d> upper_start, upper_now;
  std::vector<FollowedDot> followed;  // every followed dot
  // Every other lost dot where the tracker looks for it (`now`: its expected place): a dot
  // nearer there than where a shift puts a lower-lip dot is that one's, not the lower lip's
  // (the chin boss's dot, lost for a frame as the jaw drops, was taken for the lower lip's
  // middle dot curled under the lip).
  std::vector<FollowedDot> expected;
};

struct LowerLipSearch {
  LowerLipOptions options;  // up, down, sideways, shape: fractions of the lower lip's spacing
  // Every dot within `radius` of `centre` that may be lower-lip dot `marker` (its dot options,
  // its least contrast), nearest first.
  std::function<std::vector<Dot>(std::size_t marker, cv::Point2d centre, double radius)> dots_near;
  // Whether `dot`, found again, passes `marker`'s checks (size, contrast).
  std::function<bool(std::size_t marker, const Dot& dot)> passes;
};

struct LowerLipFound {
  std::size_t marker = 0;
  Dot dot;
};

// The mouth's frame now: the similarity (turn, scale, shift) taking the followed upper-lip and
// corner dots from their start positions `from` to their current ones `to`; none with fewer
// than two.
std::optional<cv::Matx23d> mouth_frame(const std::vector<cv::Point2d>& from,
                                       const std::vector<cv::Point2d>& to);

// The lost lower-lip dots found again together (see above; empty when no shift fits), or none
// when the lower lip was not searched so: fewer than two lower-lip dots, none of them lost and
// predicted, or no mouth frame. The tracker's single-dot search skips the lower lip's dots
// when it was searched.
std::optional<std::vector<LowerLipFound>> find_lower_lip(const LowerLipScene& scene,
                                                         const LowerLipSearch& search);

}  // namespace internal
}  // namespace rostro::tracking
