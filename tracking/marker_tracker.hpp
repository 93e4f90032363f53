#pragma once
// Follows the layout's markers through a take, frame by frame.
//
// Start: every dot and tag is detected and identified (identify.hpp), frame after frame until
// one identifies them with confidence (the frames before are written with every marker
// invalid), or the markers start where a file of starting positions puts them. Then, per
// frame:
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
//  3. each tag's whole bit pattern is aligned to the image from where LK puts its corners
//     (tag_alignment.hpp), which also checks it; a tag the pattern does not fit there is
//     re-detected in a small window around them (without align_tags: re-detected every few
//     frames, and LK on the corners in between);
//  4. an invalid marker is looked for near where its valid neighbours say it should be
//     (an affine fit of the neighbours' start positions to their current ones; a lid dot is
//     carried instead from where it was last seen with its neighbours' motion since, as the
//     eyes sit at another depth, and so is an upper-lip or mouth-corner dot, as the mouth
//     deforms far from its start; any dot so in the frame it is lost in), among every dot there,
//     nearest first, and comes back with its own identity; it is never guessed while unseen. A lid
//     dot is only accepted between its eye's corner line and not far beyond its start distance from
//     it. The lower lip's dots are looked for together, below the upper lip, and found again
//     only where their shape fits (LowerLipOptions::together). A lost marker whose neighbour
//     took its dot as the two parted after landing on one spot gets it back, and the neighbour
//     its own (TrackerOptions::swap_back_pairs). A dot found again after a loss of two frames
//     or more is reported from the next frame on (TrackerOptions::hold_found_after_lost);
//  5. every few frames with the tags read, while a dot's name is unconfirmed (named at the
//     start or found again since), the followed dots are named again from where they are,
//     the tags and the landmark model's reading of the face (TrackerOptions::
//     identity_check_every): a name is confirmed when the dot lies decisively at its own
//     place, and a dot called by another name on two checks in a row takes it;
//  6. once, a few frames after the start, the frame is identified afresh as at the start
//     (TrackerOptions::second_look_after; again later while that naming is unsure,
//     second_look_tries): where that confident naming puts a name on another dot, the take
//     starts again there, and that frame says what each renamed dot was since the start
//     (TrackedFrame::corrections, carried back by name_corrections.hpp); where it puts a name
//     only a dot's width or so off, the name keeps whichever of the two dots looks more like a
//     dot on skin (round, no dark ring: not the eye's corner or the pupil).

#include <map>
#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "tracking/apriltag_detector.hpp"
#include "tracking/brow_options.hpp"
#include "tracking/dot_detector.hpp"
#include "tracking/eye_options.hpp"
#include "tracking/face_tracker.hpp"
#include "tracking/identify.hpp"
#include "tracking/layout.hpp"
#include "tracking/lower_lip_search.hpp"
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
  // EyeOptions::inner_corners_raise_share; the mid brows: BrowOptions), and (true) for every
  // other dot. On a real face the centroid is pulled toward whatever darker lies beside a dot (a
  // brow's hair, the lip's border, a nostril, a beard's shade): on the photo scenes the 95th
  // percentile is within 0.3 px on 10 of the twelve with it, 6 without (docs/accuracy.md, "The
  // edge fit for every dot"). false: the centroid off the eyes.
  bool edge_fit_elsewhere = true;
  // The dark-ring test (DotOptions::max_surround, which tells the pupil from a dot) for the
  // dots of the eyes, the brows and the nose only (MPEG-4 groups 3, 4, 9): there a blob in a
  // dark ring is the pupil, a nostril, a lid dot against the lashes seen from a brow dot. Elsewhere
  // a dot in a dark ring lies on a dark patch of its own (the shadow under the lower lip, a
  // dim cheek), and the test lost it there (the photo scenes: hand, gradient). The first
  // frame's search keeps the test everywhere. false: every dot.
  bool surround_test_upper_face_only = true;
  int lk_window = 13;               // pixels
  int lk_levels = 2;                // pyramid levels above the image: motion up to ~25 px/frame
  double region_margin_px = 24;     // LK region: the markers' box + this + the top window
  double max_fb_error = 1.0;        // pixels, forward-backward round trip
  double max_snap = 2.5;            // pixels between LK's answer and the dot's centre
  double min_contrast_ratio = 0.4;  // of the dot's contrast at identification
  // A followed dot measured smaller than this share of its size in the frame before is dropped
  // for the frame: something has taken a bite out of it, and its centre has moved away from the
  // bite. The edge of a passing hand does that on its first or last frame over a dot, and noise
  // in low light eats into a small dot's rim. A dot turning edge-on shrinks too, but by a few
  // per cent a frame (at 100 degrees a second); compared with a running mean instead of the
  // frame before, such a dot was dropped and found again on the eye's corner
  // (EyeCornerMerge tests). A dot not measured since the start is judged the same way when it
  // is first found, against the size it was given there (the other dots'): a blob that much
  // smaller, where it is looked for, is something else (the mouth's own corner, a brow hair).
  // Measured on the photo scenes no rule was tuned on: docs/accuracy.md, "A dot that suddenly
  // shrinks". 0: off.
  double min_recent_size = 0.85;
  double tag_margin = 0.3;            // tag search window: expected box + this x tag size
  double tag_decimate_above_px = 48;  // tags wider than this are searched at half resolution
  // Each tag's corners aligned each frame to its whole printed pattern from where LK moves
  // them (tag_alignment.hpp): a few hundredths of a pixel instead of a tenth or more. A tag the
  // pattern does not fit there is detected again. Off: LK's corners, the tags re-detected
  // every tag_redetect_every frames.
  bool align_tags = true;
  int tag_redetect_every = 4;     // frames, without align_tags; in between LK follows the corners
  double search_fraction = 0.45;  // re-acquisition radius, fraction of the nearest spacing
  // A lost dot is found again only on a blob that looks like it at most this much less like a
  // dot (Dot::surround + elongation - 1) than it has looked while followed: a clean dot on the
  // cheek is not found on the eye's corner or a lip corner beside it, a lid dot against its
  // lashes still on itself. Negative: any blob that passes the dot checks.
  double found_look_allowance = 0.2;
  // Two dots that land on one spot for a frame and part again (a brow raised at once, the chin
  // boss dropped onto the chin's place) can leave LK following one name on the other's dot, that
  // name's own dot free and the other name lost. A lost marker then takes the dot its valid
  // neighbour follows, and the neighbour the free dot nearer its own place, when the pair's
  // offset is decisively the layout's that way round and not the other (on two frames in a row;
  // MarkerTracker::Impl::swap_back_pairs), and the frames since the lost one was lost are
  // corrected (TrackedFrame::corrections). The marker suite's fast mouth: 115 swapped
  // observations -> 15; not tuned on (data/eval/suite_sudden.json): 115-140 -> 0-16; the photo
  // scenes and the closed loops unchanged. false: never.
  bool swap_back_pairs = true;
  // A dot found again after at least this many frames lost (by a search near where its
  // neighbours put it, or by the second look; not a followed dot renamed) is followed from that
  // frame but reported from the next, when LK has carried it there and it still passes every
  // check (MarkerState::held, LostReason::FoundAgain). What hid it may still be at its edge on
  // the frame it comes out: a passing hand's edge bites into it and pulls its centre off. One
  // frame lost is a dropout (blur, low light), not something passing over: such a dot is
  // reported at once (held too, low light lost three times as many observations for the same
  // gain). The held-out photo scenes: 23 observations reported under the hand -> 15, 38 astray
  // -> 27, 382 more lost (of 132,592), the hand's dots back after 2 frames instead of 1;
  // docs/accuracy.md, "Reported from the frame after it is found". 0: never held.
  int hold_found_after_lost = 2;
  // How far a dot's frame-to-frame motion may differ from its neighbours' (the larger of a
  // fraction of its spacing at the start, and pixels): expressions, not jumps to another dot.
  double max_relative_motion = 0.35;
  double max_relative_motion_px = 4;
  // The eye dots' rules (lids and corners: eye_options.hpp), the brow dots' (brow_options.hpp) and
  // the lower lip's (lower_lip_search.hpp).
  EyeOptions eyes;
  BrowOptions brows;
  LowerLipOptions lower_lip;
  int min_identified = 3;  // markers needed to start tracking
  // When an identification is confident enough to start on (identify.hpp).
  IdentificationOptions identification;
  // Every this many frames, with the tags read and a dot's name unconfirmed, the followed dots
  // are named again from their places, the tags and, with a landmark model, the face's shape
  // (identify.hpp). A dot decisively nearer another name's place than its own (within 0.4 of
  // the distance) on two checks in a row takes that name when no followed dot holds it, or
  // when its holder moves on in turn; the name it leaves is lost (LostReason::Identity), and
  // the frame reports the renaming. 0: never.
  int identity_check_every = 10;
  // This many frames after the start, the whole frame is identified again as at the start
  // (the tags detected, every dot found, the landmarks fitted); when that naming is confident,
  // no less sure than the start's (IdentificationConfidence::margin at least as large), and
  // puts any followed name more than half its spacing from where it is followed, tracking
  // starts again on this frame (the frame reports "identified again"). A start is the first
  // confident frame, which may still be smeared by motion (a blur fading out) or show a face
  // half in view: the dots merged with the features beside them (a lip corner, the eye's
  // corner) are named on those features there, and LK follows them to the end; a few frames on
  // they stand apart. The frames before keep the first names. When no name is that far off,
  // a name the naming puts more than a dot's width away (or finds while it is lost) goes to
  // the naming's dot where that looks more like a dot (Dot::surround + elongation - 1 smaller)
  // and no other followed dot is there ("second look: ... placed"). 0: never.
  int second_look_after = 10;
  // A second look whose naming is not confident, or less sure than the start's, cannot judge
  // the names followed by itself; it is tried again second_look_after frames later, up to this
  // many looks, and such a later look renames only the names the confident look before it
  // renamed: two namings against the start's one. A start on a frame still smeared by a fading
  // blur is sure for a wrong reason: the blur washes out the face's own dark features, the
  // rivals its margin is measured against (a held-out photo scene: the left mouth corner's dot,
  // merged with the moustache, named on the lip corner 25 px away with a margin of 0.96; the
  // looks 10, 20 and 30 frames on, margins 0.40, 0.71 and 0.68, the last two moving that name
  // to its dot). A later look alone is no better evidence than the start: on a dim face the
  // third, as sure as the start by its margin, moved the lower lip's names onto wrong dots.
  int second_look_tries = 3;
  // Threads the followed dots' centres are measured on each frame (0: the machine's cores;
  // OpenCV's cv::setNumThreads caps them). Any count gives the same tracks: each dot is
  // measured on its own, then all are judged and applied in layout order.
  int threads = 0;

  // Throws InputError naming the first option out of range (lk_window <= 0,
  // eyes.max_dot_growth_found < 1, ...), this struct's or a part's. MarkerTracker's
  // constructor calls it.
  void validate() const;
};

// Sets one field of `options` from "NAME=VALUE", NAME a field's name as above (a region's or
// DotOptions' field as "eyes.NAME", "brows.NAME", "lower_lip.NAME", "dots.NAME"), e.g.
// "eyes.max_dot_growth_found=1.3" or "lower_lip.together=false": for
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
  LidElongation,  // a lid dot's blob longer than max_lid_elongation
  Contrast,       // below min_contrast_ratio of its contrast at the start
  Shrunk,         // under half its start size, or min_recent_size of its last (or given) size
  Growth,         // over twice its start size; an eye dot found again, past max_dot_growth_found
  Jump,           // moved unlike its neighbours (max_relative_motion, max_relative_motion_px)
  Coincident,     // on the spot of another dot (both are dropped)
  Identity,       // its dot took another name at an identity check during the take
  TagLost,        // a tag not detected again near where LK moved its corners
  TooFew,         // followed, but in a frame that kept fewer markers than a start needs
  FoundAgain,     // found again this frame: followed on, reported from the next (held)
};
inline constexpr int kLostReasonCount = static_cast<int>(LostReason::FoundAgain) + 1;
// A few words: "round trip", "too few", ...
const char* to_string(LostReason reason);

// One marker's state as the overlay draws it.
struct MarkerState {
  const MarkerSpec* spec = nullptr;
  bool valid = false;  // followed this frame
  // Valid but not reported this frame (TrackerOptions::hold_found_after_lost); its lost_reason
  // is FoundAgain.
  bool held = false;
  LostReason lost_reason = LostReason::Unidentified;  // None while valid and not held
  cv::Point2d position;
  std::array<cv::Point2d, 4> corners{};  // tags only
  double quality = 0;
  int lost_frames = 0;  // frames since it was last valid
};

// How long one named step of a track() call took (wall time).
struct StepTime {
  const char* step;  // "pyramid", "lk_round_trip", "snap_dots", ... (track(), Impl::follow())
  double ms = 0;
};

class MarkerTracker : public FaceTracker {
 public:
  MarkerTracker(MarkerLayout layout, TrackerOptions options = {});
  ~MarkerTracker() override;

  // Start from these positions (layout id -> pixels) instead of identifying automatically.
  void set_start_positions(const std::map<std::string, cv::Point2d>& positions);

  // `image`: 8-bit grey or BGR. Every layout marker appears in the result, in layout order.
  TrackedFrame track(const cv::Mat& image, long frame, double time_s) override;

  bool started() const override;
  // A MarkerTracker with these options, started from `start`'s valid positions.
  std::unique_ptr<FaceTracker> started_from(const TrackedFrame& start) const override;
  // A second look renames dots followed since the start (step 6 above) up to
  // second_look_after x second_look_tries frames after it; a pair's names given back
  // (swap_back_pairs) correct the frames since its lost name was lost, of which a consumer
  // holding this many frames (at least 30 with swap_back_pairs) corrects those it holds.
  long correction_horizon() const override;
  // The identification tracking started from (confident) once started; before, the latest
  // doubtful one, saying why (IdentificationConfidence::doubt). Empty (0 dots) with starting
  // positions or before the first frame.
  const IdentificationConfidence& identification() const;
  // The frame tracking started on; -1 before.
  long started_at() const;
  const std::vector<MarkerState>& states() const;
  const MarkerLayout& layout() const override;
  void draw(cv::Mat& image, long frame) const override;  // tracking/overlay.hpp
  // The named steps of the last track() call in the order they ran, each with its time: on a
  // followed frame the pyramid, the LK round trip, the snap, the tags, the drop rules and the
  // re-acquisition; on a first frame the tag detection and the identification. bench_tracking
  // reports them one by one.
  const std::vector<StepTime>& step_times() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rostro::tracking
