#pragma once
// MarkerTracker's state and steps (MarkerTracker::Impl), shared by the files that carry them
// out: marker_tracker.cpp (setting up, the frame's order of steps, the options),
// marker_start.cpp (naming the markers at the start of a take), marker_identity.cpp (checking
// the names during the take), marker_follow.cpp (following the markers from frame to frame)
// and marker_reacquire.cpp (finding lost markers again). Private to tracking/.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>
#include <optional>
#include <set>
#include <type_traits>

#include "facecore/named_options.hpp"
#include "facecore/option_check.hpp"
#include "tracking/affine2d.hpp"
#include "tracking/eye_options.hpp"
#include "tracking/face_prior.hpp"
#include "tracking/identify.hpp"
#include "tracking/lk_pyramid.hpp"
#include "tracking/lower_lip_search.hpp"
#include "tracking/marker_tracker.hpp"
#include "tracking/overlay.hpp"
#include "tracking/tag_alignment.hpp"

namespace rostro::tracking {

using namespace internal;  // the eyes' geometry and the lower lip's search

namespace internal {

// DotOptions::max_surround that no ring reaches: no dark-ring test.
inline constexpr double kNoSurroundTest = 1e9;

inline cv::Point2d mean_of(const std::array<cv::Point2d, 4>& c) {
  return (c[0] + c[1] + c[2] + c[3]) * 0.25;
}

inline cv::Rect box_around(const std::array<cv::Point2d, 4>& corners, double margin) {
  double x0 = 1e18, y0 = 1e18, x1 = -1e18, y1 = -1e18;
  for (const auto& p : corners)
    x0 = std::min(x0, p.x), y0 = std::min(y0, p.y), x1 = std::max(x1, p.x), y1 = std::max(y1, p.y);
  return {static_cast<int>(x0 - margin), static_cast<int>(y0 - margin),
          static_cast<int>(x1 - x0 + 2 * margin) + 1, static_cast<int>(y1 - y0 + 2 * margin) + 1};
}

// Each dot's part of the face, from its MPEG-4 feature point: which region rules apply to it.
// The eyes (group 3) are where a dot meets dark things that are no markers (the pupil, the
// iris, the lash line, the other lid's dot); the brows (group 4) and the eyes lie at other
// depths than their neighbours; the lower lip moves unlike the dots around it.
enum class DotRole {
  Lid,             // 3.1-3.4: the upper and lower lids' midpoints
  InnerEyeCorner,  // 3.8, 3.11
  OuterEyeCorner,  // 3.7, 3.12
  OtherEye,        // any other point of group 3 (the pupils): an eye dot with no rule of its own
  MidBrow,         // 4.3, 4.4: above the eyebrow's highest point
  LowerLip,        // 8.2, 8.7, 8.8 (lower_lip_search.hpp)
  Plain,           // every other dot, and the tags
};

inline DotRole role_of(const FeaturePointId& fp) {
  constexpr int kLeftOuterCorner = 7, kRightOuterCorner = 12;
  if (is_eyelid_midpoint(fp)) return DotRole::Lid;
  if (is_inner_eye_corner(fp)) return DotRole::InnerEyeCorner;
  if (is_eye_point(fp))
    return fp.index == kLeftOuterCorner || fp.index == kRightOuterCorner ? DotRole::OuterEyeCorner
                                                                         : DotRole::OtherEye;
  if (fp.group == 4 && (fp.index == 3 || fp.index == 4)) return DotRole::MidBrow;
  if (at_lower_lip(fp)) return DotRole::LowerLip;
  return DotRole::Plain;
}

inline bool on_chin(const FeaturePointId& fp) {
  return fp.group == 2 && (fp.index == 1 || fp.index >= 10);
}

inline bool at_eye(DotRole r) {
  return r == DotRole::Lid || r == DotRole::InnerEyeCorner || r == DotRole::OuterEyeCorner ||
         r == DotRole::OtherEye;
}

// Whether a dot lies among the face's dark round features, where a blob in a dark ring is one
// of them (the pupil in its iris, a nostril, a lid dot against its lashes seen from a brow
// dot): the eyes, the brows and the nose (TrackerOptions::surround_test_upper_face_only).
inline bool by_dark_features(const FeaturePointId& fp) {
  return fp.group == 3 || fp.group == 4 || fp.group == 9;
}

}  // namespace internal

struct MarkerTracker::Impl {
  MarkerLayout layout;
  TrackerOptions options;
  AprilTagDetector full_detector;
  AprilTagDetector window_detector;  // small windows: full resolution
  std::vector<MarkerState> states;
  // At the start of tracking: positions (seen or predicted), tag corners, dot looks.
  std::vector<cv::Point2d> reference;
  std::vector<bool> reference_seen;  // the start position was measured, not predicted
  std::vector<std::array<cv::Point2d, 4>> reference_corners;
  std::vector<double> reference_contrast, reference_diameter;
  std::vector<double> spacing;  // nearest other marker at the start, pixels
  std::map<std::string, cv::Point2d> start_positions;
  bool started = false;
  long started_at = -1;
  IdentificationConfidence identification;
  FacePrior face_prior{options.identification.face_model};
  std::map<std::string, cv::Point2d> expected_start;  // Identification::places
  std::string note;                                   // this frame's TrackedFrame::identification
  // This frame's TrackedFrame::corrections and their first frame (the second look's renames).
  std::vector<NameCorrection> corrections;
  long corrected_since = -1;
  cv::Mat gray;          // this frame; a view of the caller's image when it is grey already
  cv::Mat gray_storage;  // conversion buffer for colour input, reused frame to frame
  // The LK pyramids cover only the region the markers occupy (plus room for motion), not the
  // whole frame: at 1280x720 a fifth to a half of the pixels. LK needs both pyramids of one
  // size, so the region keeps its size from frame to frame and only moves; it is resized
  // (the new frame's pyramid built twice) when the markers outgrow it or shrink well inside.
  LkPyramid previous_pyramid, pyramid;
  cv::Rect previous_region, region;

  Impl(MarkerLayout l, TrackerOptions o);

  std::vector<DotRole> roles;  // per marker, from its feature point

  // TrackerOptions::threads, 0 resolved to the machine's cores.
  const int threads;

  // Runs job(0) .. job(count - 1), independent of one another, on up to `threads` threads
  // (OpenCV's pool, which also caps them: cv::setNumThreads), and returns when all are done.
  // Stripe t takes jobs t, t + stripes, t + 2 stripes, ...: neighbouring jobs (one face
  // region's dots, the eyes' dearer ones together) go to different threads.
  template <typename Job>
  void for_each_in_parallel(size_t count, const Job& job) const {
    const auto stripes = static_cast<size_t>(std::min<long>(threads, static_cast<long>(count)));
    if (stripes <= 1) {
      for (size_t i = 0; i < count; ++i) job(i);
      return;
    }
    cv::parallel_for_(
        cv::Range(0, static_cast<int>(stripes)),
        [&](const cv::Range& r) {
          for (auto t = static_cast<size_t>(r.start); t < static_cast<size_t>(r.end); ++t)
            for (size_t i = t; i < count; i += stripes) job(i);
        },
        static_cast<double>(stripes));
  }

  AprilTagOptions with_layout_families(AprilTagOptions o) const;
  static AprilTagOptions window_options(AprilTagOptions o);

  // Colour input is converted to grey only where the tracker looks (the pyramid region and
  // the windows it searches), not over the whole frame: at 1280x720 the full conversion
  // costs about 0.3 ms, a fifth of a frame's tracking.
  const cv::Mat* colour = nullptr;
  std::vector<cv::Rect> converted;

  void to_gray(const cv::Mat& image);

  // Makes sure the grey image holds this frame's pixels inside `r`.
  void ensure_gray(cv::Rect r);
  void ensure_gray_around(cv::Point2d p, double radius);

  // ---- the region the pyramids cover ----------------------------------------------------

  // The markers' bounding box (last known places, tag corners included) with room for a
  // frame's motion and the LK window at the top level.
  cv::Rect needed_region() const;

  // A region of `size` centred on `want`, inside the image.
  cv::Rect placed(cv::Size size, const cv::Rect& want) const;

  // The size a region should get when it is (re)sized: the need plus a tenth each way, so
  // that ordinary motion and expressions do not resize it again.
  cv::Size grown(const cv::Rect& need) const;

  bool fits(cv::Size size, const cv::Rect& need) const;

  void build_pyramid(const cv::Rect& r, LkPyramid& out) const;

  // Runs one named step, recording its time in step_times.
  std::vector<StepTime> step_times;
  template <typename Step>
  auto timed(const char* name, Step&& step) {
    const auto t0 = std::chrono::steady_clock::now();
    const auto record = [&] {
      step_times.push_back(
          {name, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                     .count()});
    };
    if constexpr (std::is_void_v<decltype(step())>) {
      step();
      record();
    } else {
      auto result = step();
      record();
      return result;
    }
  }

  // ---- start of the take ---------------------------------------------------------------

  // Second looks tried since the take last started from scratch; second_look_tries once one
  // has judged the names.
  int looks = 0;
  std::vector<std::string> moved_before;  // the names the last confident look moved
  // The margin is a lower quartile of gaps capped at half a spacing: two confident namings of
  // the same face differ by a few hundredths near the cap, which tells neither from the other.
  static constexpr double kMarginNoise = 0.1;
  // One dot can merge with a feature or hide on any frame; a naming that explains two fewer
  // dots than the start's explains the face worse, however sure its margin (a drive's first
  // jerk smears the mouth's dots onto the lips and teeth).
  static constexpr int kMatchedNoise = 1;

  // 6. (TrackerOptions::second_look_after.) The frame named afresh; where the naming is
  //    confident, about as sure as the start's (IdentificationConfidence::margin, within
  //    kMarginNoise), explains about as many dots (within kMatchedNoise) and moves a followed name
  //    onto another dot, the take starts again here on that naming. Where it only puts names a
  //    dot's width or so from where they are followed, each of those names goes to whichever of the
  //    two dots looks more like a dot (placed_by_look). A naming too unsure to judge by is tried
  //    again second_look_after frames later, up to second_look_tries times; such a later look
  //    renames only what the confident look before it renamed: two namings against one, however
  //    sure the start's was. Returns false when the naming was too unsure to judge the followed
  //    names by.
  bool second_look(long frame);

  // "a" or "a, ...": a list of names in a frame's note.
  static std::string first_and_more(const std::vector<std::string>& names);

  // A dot worn on the skin is round and has no dark ring around it; the face's own dark
  // features beside the dots (the eye's corner, the pupil in its iris, the lip corner) are
  // elongated or lie in darker surroundings. Zero for a clean dot, larger the less like one.
  static double unlike_a_dot(const Dot& d) { return d.surround + (d.elongation - 1); }

  // The names the second look's naming puts more than a dot's width from where they are
  // followed (or finds while they are lost), each placed on the naming's dot where that looks
  // more like a dot than the one followed and, for a followed name, about as much like its own
  // dot as it has looked (TrackerOptions::found_look_allowance, as when a lost dot is found), and
  // no other followed dot is on it. Which of the two
  // is the dot cannot be told by where they lie: LK carries an eye dot onto the eye's corner
  // while a blur fades (the followed one is wrong), and the landmarks that place the names lie
  // toward the eyes' dark features on the rendered head (the naming is wrong).
  std::vector<std::string> placed_by_look(const Identification& id);

  std::vector<TagDetection> detect_all_tags();

  void start();

  bool enough(size_t placed) const;

  // Tracking begun from the markers placed (frontal layout position -> image position); false,
  // nothing changed but the states' places, with too few of them.
  bool begin(const std::vector<std::pair<cv::Point2d, cv::Point2d>>& known);

  // The markers found where the file of starting positions puts them (within a few pixels), as
  // frontal layout position -> image position.
  std::vector<std::pair<cv::Point2d, cv::Point2d>> find_at_start_positions(
      const std::vector<TagDetection>& tags);

  // The dots found on the whole frame named (identify.hpp). With a landmark model at hand,
  // the layout's arrangement alone is not enough to start on: on a real face it names the
  // lower face a row off (the dots of a smile, a long jaw). The face is found on a later frame
  // (it entered, turned back, came into focus).
  Identification name_frame(const std::vector<TagDetection>& tags);

  // The markers placed where `id` names them, as frontal layout position -> image position.
  std::vector<std::pair<cv::Point2d, cv::Point2d>> adopt(const Identification& id);

  // Where dlib's landmarks put the layout's dots on the face the tags are on (face_prior.hpp).
  std::map<std::string, cv::Point2d> expected_places(const std::vector<TagDetection>& tags);

  // The layout's frontal millimetres to pixels, as the tags read place it.
  std::optional<cv::Matx23d> layout_to_image(const std::vector<TagDetection>& tags) const;

  // Where the unseen markers should be: the layout mapped by the seen ones.
  void place_unseen(const std::vector<std::pair<cv::Point2d, cv::Point2d>>& known);

  // The seen markers' start positions, and the seen dots' contrast and size (returned: the
  // contrasts and sizes of the dots measured, in marker order).
  std::pair<std::vector<double>, std::vector<double>> measure_seen();

  // The pixel-valued options scaled to the dots' typical size (px, large_dots); the dots not
  // measured at the start take the typical contrast and size.
  void scale_to_dots(const std::pair<std::vector<double>, std::vector<double>>& measured);

  // Each marker's nearest other marker at the start.
  void measure_spacing();

  // ---- per frame -----------------------------------------------------------------------

  // The pixel-valued options are for dots `reference_dot_px` wide; larger dots (a larger
  // image of the face) move, blur and round-trip LK by proportionally more pixels. The LK
  // window grows only with the square root: it must hold the larger dot, but a window grown
  // in proportion takes in the dark open mouth beside a lip dot (Xface fear at 1280x720: the
  // chin boss lost, the chin found again on its dot), while one kept at 13 px loses the upper
  // lip's dots when the mouth opens at once (Xface joy at 2.4 s: both corners then judged
  // against the lower lip only, dropped and found again a dot off).
  double px = 1;            // the dots' size at the start over reference_dot_px, at least 1
  bool large_dots = false;  // the dots at the start at least reference_dot_px wide
  double max_fb_error() const { return options.max_fb_error * px; }
  double max_snap() const { return options.max_snap * px; }
  int lk_window() const;

  // The first check dot d fails as marker i (None: it passes). Any dot may be at most twice its
  // start size; a followed eye dot too: blurred it grows as much as merged, and where it was
  // dropped for that it came back on a neighbour (docs/accuracy.md, the photo scenes' blur).
  LostReason dot_check(size_t i, const Dot& d, bool followed) const;
  // At the eye a blob found where a lost dot was may be the dot merged with something dark
  // beside it: the pupil beside a lid dot as the lid closes, the other lid's dot in a blink.
  // Its centre is the pair's and neither marker's, so it is not taken. The dot may have turned
  // toward the camera meanwhile, so after a long loss it may be a little larger than it was
  // then (`recent_diameter`, its last sizes measured, smoothed) or at the start, not as large
  // as two dots (after a short one, than it was then, when it was seen edge-on: merged with a
  // dark neighbour it is about its start size). The largest blob eye dot i is found again on.
  double largest_found(size_t i) const;
  bool dot_passes(size_t i, const Dot& d, bool followed) const;
  // (DotRole.) Around the mouth, where the lips' dark line and the open mouth are, a dot
  // merged for a frame is better kept than dropped (the suite's mouth clip: dropped lip dots
  // come back on a neighbour's): the eye dots' stricter checks hold only at the eyes.
  bool at_eye(size_t i) const { return tracking::at_eye(roles[i]); }
  // How dot i is measured: the edge fit (the centroid where TrackerOptions::edge_fit_elsewhere
  // or, for the mid brows, BrowOptions::edge_fit_mid_brows is off), and at the inner eye corners
  // the raised share (EyeOptions::inner_corners_raise_share) and the symmetric centre
  // (inner_corners_symmetric_centre). The raised share not at the other eye dots: on the lid dots
  // the raised share would take two lid dots merged in a blink (not round at half, round enough
  // higher up, where 0.4 passes); on the outer corners at 640x480 it found dots lost before at 0.6
  // with the line still on, and the edge fit then put 1 in 8 of them 1-1.6 px off (Xface fear: head
  // yaw 9.4 -> 12.7 %).
  DotOptions centroid_dots, inner_corner_dots, inner_corner_dots_large;
  // As options.dots and centroid_dots, for the dots off the eyes, the brows and the nose: the
  // lips, the jaw, the cheeks (TrackerOptions::surround_test_upper_face_only).
  DotOptions lower_face_dots, lower_face_centroid_dots;
  // Per marker, set in the constructor: [large_dots][i].
  std::array<std::vector<const DotOptions*>, 2> measured_with;
  const DotOptions& dot_options(size_t i) const { return *measured_with[large_dots ? 1 : 0][i]; }
  bool is_lid(size_t i) const { return roles[i] == DotRole::Lid; }
  bool carried_while_lost(size_t i) const {
    return is_lid(i) || at_upper_lip_or_corner(states[i].spec->feature_point);
  }
  double face_scale = 1;                  // the face's size now over its size at the start
  std::vector<double> recent_diameter;    // per dot, smoothed over its last measurements
  std::vector<double> recent_elongation;  // per dot, when last measured
  std::vector<double> last_diameter;      // per dot, when last measured
  // Per dot, how unlike a dot it has looked while followed (unlike_a_dot), smoothed over its
  // measurements: from the start's, then each frame it is followed.
  std::vector<double> usual_look;

  // ---- per frame: the steps --------------------------------------------------------------

  // One frame's LK: the points followed from the previous frame (the valid dots and the valid
  // tags' corners), where LK moves them and where it brings them back.
  struct Flow {
    std::vector<cv::Point2f> before, after, back;
    std::vector<size_t> owner;  // state index per point
    std::vector<uchar> status, status_back;
    std::vector<bool> was_valid;  // per marker, at the end of the previous frame
  };
  // Point k failed LK's forward-backward round trip (TrackerOptions::max_fb_error).
  bool failed_round_trip(const Flow& f, size_t k) const;
  // Each valid tag's corners where LK moved them, and whether all four made the round trip.
  struct TagGuesses {
    std::vector<std::array<cv::Point2d, 4>> corners;
    std::vector<bool> held;
  };

  void follow(long frame);

  static constexpr double kDecisive = 0.4;  // other place's distance / own place's, at most
  std::map<std::string, std::string> called_otherwise;  // the last check's misnamed dots
  std::set<size_t> unconfirmed;  // dots named since the last check that confirmed them

  // 5. The followed dots named again from their places, the tags read and, with a landmark
  //    model, the face's own shape (TrackerOptions::identity_check_every). A take can start
  //    on a wrong name (a dot too faint to be found at the start, its neighbour's dot nearer
  //    its place) or take one on (re-acquisition chooses a name); LK then follows the wrong
  //    name to the end. Only a name not yet confirmed is in question: a face deforming beyond
  //    the arrangements the naming knows (the jaw dropped, the chin boss at the chin's flat
  //    place) fools the naming, not LK following a dot from a confirmed name. The naming is
  //    trusted only when confident, and with a landmark model only when the landmarks agree
  //    with the tags (as at the start).
  void check_identities();

  // The calls (state index -> the index of its new name) that can be followed: a dot takes a
  // name no followed dot holds, or one whose holder takes another in turn (a chain), or the
  // dots of a ring each take the next one's name. A chain ending in a name its holder keeps
  // stays as it is.
  std::vector<std::pair<size_t, size_t>> moving_together(const std::map<size_t, size_t>& calls);

  // Each (from, to) dot takes the name `to`; a name left behind is lost (LostReason::Identity),
  // and the frame reports the renaming.
  void rename(const std::vector<std::pair<size_t, size_t>>& moves);

  // Layout dot id -> pixels where the landmark model puts the dots on the face the tags
  // place, fitted without searching the frame (face_prior.hpp) in the box the tags give it.
  // (Not the followed dots' box: dots under wrong names would place it.) Empty without a model.
  std::map<std::string, cv::Point2d> face_places(const std::vector<TagDetection>& tags);

  // 1. LK on the valid dots and the valid tags' corners, forward and back.
  Flow lk_round_trip();

  TagGuesses tag_corner_guesses(const Flow& f) const;

  // 2. Each dot that made LK's round trip snapped to its measured centre, if that passes the
  //    checks; the others turn invalid.
  void snap_dots(const Flow& f);

  // 3. A tag is rigid: LK moves its corners, and its whole printed pattern aligned from there
  //    (TrackerOptions::align_tags) gives them; a tag the pattern does not fit there (a hand
  //    over part of it, LK gone astray) is re-detected near the moved corners, then aligned.
  //    Without the alignment, LK's corners are kept between detections (every few frames) as
  //    long as all four pass the round trip and the square keeps its size.
  void follow_tags(const Flow& f, const TagGuesses& g);

  // Tag i's corners from its whole printed pattern (tag_alignment.hpp) aligned from `start`,
  // several times nearer than the square's edges that detection and LK give: the tags carry
  // the head's pose. False, the state untouched, when the pattern does not fit there.
  std::vector<std::optional<TagAligner>> aligners;  // per marker: tags only
  bool align_tag(size_t i, const std::array<cv::Point2d, 4>& start);

  // 4a. A dot must move roughly as its neighbours do: LK that slid onto another dot (a
  //     neighbour's, while its own was hidden) moves very differently from them.
  void drop_jumped(const Flow& f);

  // 4b. Two dots on one spot: neither can be trusted (an identity swap is worse than a gap).
  void drop_coincident();

  // 5. Look again for the markers that are not valid, where their neighbours put them.
  void reacquire_lost(const Flow& f);

  // 5b. TrackerOptions::swap_back_pairs. A lost marker b whose valid neighbour a (within two of
  //     b's spacings) follows a dot away from a's place, with a free dot nearer a's place, is
  //     where two dots landed on one spot for a frame or more (a brow raised at once, the chin
  //     boss dropped onto the chin's place) and LK carried a's name on with b's dot when they
  //     parted. a's place comes from the face's fit of every valid marker, moved with the jaw
  //     for the jaw's dots (moved_with_jaw), so not from a's own dot. The pair's offset decides:
  //     b on a's dot and a on the free one must give an offset from a to b decisively nearer
  //     the layout's (as the face's fit maps it) than the other way round (kDecisive), on two
  //     frames in a row. A dot a has followed away from its place, beside a free spot where it
  //     was (a brow raised, a mole), keeps its name: the offset is across, not along, the pair.
  void swap_back_pairs(long frame);
  // How many frames a take written as it goes holds for the frames given out under swapped
  // names to be corrected (MarkerTracker::correction_horizon): a second at 30 fps, where the
  // marker suite's fast mouth gives its names back 12-16 frames after the dots landed.
  static constexpr long kSwapBackReach = 30;
  std::optional<cv::Matx23d> face_fit;  // predict_lost's fit of every valid marker, this frame
  std::set<std::pair<size_t, size_t>> pair_calls_before;  // (a, b): the last frame's calls
  int frames_since_tag_detection = 0;

  // Side lengths within 10% of the last ones: LK did not slide a corner along an edge.
  static bool keeps_shape(const std::array<cv::Point2d, 4>& was,
                          const std::array<cv::Point2d, 4>& now);

  // The centre of a square seen in perspective: where its diagonals cross (as libapriltag's
  // centre, the homography's image of the tag centre).
  static cv::Point2d diagonal_crossing(const std::array<cv::Point2d, 4>& c);

  // Tag i detected again in a window around `guess` (and aligned to its pattern, align_tags);
  // false, the tag invalid, when it is not there.
  bool find_tag(size_t i, const std::array<cv::Point2d, 4>& guess);

  // Where each invalid marker should be: an affine fit of its nearest valid neighbours'
  // start positions to their current ones, checked against the fit of all valid markers.
  std::vector<cv::Matx23d> prediction_fit;
  std::vector<bool> has_prediction;
  std::vector<cv::Point2d> predicted;

  cv::Point2d predicted_at(size_t i) const { return predicted[i]; }

  void predict_lost();

  // `global` moved by its miss at the followed jaw dot nearest dot i at the start (i aside;
  // `global` itself when there is none): the face's fit follows the skull, and an open jaw
  // carries the chin tens of pixels below where it puts it, onto the lower lip's dot.
  cv::Matx23d moved_with_jaw(const cv::Matx23d& global, size_t i) const;

  // A lid dot lies at another depth than its neighbours, so under a head turn the start
  // positions' fit puts it pixels off (onto the eye corner, for a lower lid: 23 px in the
  // closed loop's turns). While it is lost it is carried instead from where it was last seen,
  // with the motion of the neighbours that were valid then (a few frames: nearly a shift).
  // So are the upper lip's and the mouth corners' dots (carried_while_lost): a mouth drawn in
  // or stretched leaves the start's arrangement far behind (the marker suite's fast mouth puts
  // the right corner 26 px from where the fit does, within 4 px of the upper lip's dot, and the
  // upper lip's name took the corner's dot when both were lost).
  // Other dots are carried only in the frame they are lost in: there their last place is
  // still the best guess (Xface fear: the chin boss, lost as the hidden lower-lip dot came
  // back into view 14 px above it, was looked for where the start positions' fit put it, on
  // that lip dot, and the chin then took the chin boss's dot for the rest of the take). Carried
  // longer, a wrong last place is carried along too: every dot carried, the held-out photo
  // scenes had 51 observations astray instead of 25 (the right mid-brow's name found again
  // 14-17 px from its dot, on two scenes).
  struct LastSeen {
    bool known = false;
    cv::Point2d position;
    std::vector<std::pair<size_t, cv::Point2d>> anchors;  // neighbour -> its position then
  };
  std::vector<LastSeen> last_seen;

  void remember_last_seen(const std::vector<bool>& was_valid,
                          const std::vector<cv::Point2f>& before, const std::vector<size_t>& owner);

  std::optional<cv::Point2d> carried(size_t i) const;

  void reacquire(size_t i);

  // TrackerOptions::found_look_allowance. The blob is measured again as a followed dot is
  // (from its own centre, within max_snap): found among the dots near a place, a dot merged
  // with a darker neighbour (a big brow dot against the eyebrow) measures as part of it.
  bool looks_like_itself(size_t i, const Dot& d) const;

  // Marker i found on dot d where LK did not follow it there: its look as measured now, its
  // quality its contrast against the start's, below a followed dot's.
  void found_on(size_t i, const Dot& d);

  // A lid carried from where it was last seen moves up and down with the lid meanwhile, but
  // hardly sideways: a dot well to the side of where it is carried is an eye corner's.

  // ---- the lower lip (lower_lip_search.hpp) ---------------------------------------------

  bool at_lower_lip(size_t i) const { return roles[i] == DotRole::LowerLip; }
  // LowerLipOptions::with_the_jaw: the dots the jaw carries.
  bool on_jaw(size_t i) const { return at_lower_lip(i) || on_chin(states[i].spec->feature_point); }
  bool placed_by_jaw(size_t i) const { return options.lower_lip.with_the_jaw && on_jaw(i); }
  // The lower lip opens with the jaw by up to a spacing in a frame (Xface joy), unlike the
  // upper lip and the corners: its dots are no measure of how theirs should move
  // (LowerLipOptions::together), nor theirs of how its dots should (with_the_jaw: the jaw's
  // dots are).
  bool apart_from_lower_lip(size_t i, size_t j) const;

  // A lower-lip dot not seen when tracking started has a start place that is the
  // identification's guess: the shape the together search matches is where the dots were
  // seen, so such a dot is looked for on its own, where its neighbours put it (the photo
  // scene with a hand: the three lower-lip dots unnamed at the start, found together with the
  // middle one's name on its neighbour's dot).
  bool searched_with_lower_lip(size_t i) const { return at_lower_lip(i) && reference_seen[i]; }

  // LowerLipOptions::together: the lower lip's lost dots found again together
  // (find_lower_lip). Returns whether the lower lip was searched so (the single-dot search
  // then skips its dots).
  bool reacquire_lower_lip();

  // A dot that belongs to a valid neighbour, or lies about as near another lost marker's
  // expected place as this one's (IdentificationOptions::unnamed_rival, as at the start), is
  // not marker i.
  bool belongs_to(size_t i, cv::Point2d at, double scale) const;
  // A followed dot lies within half its spacing (times `scale`, the face's) of `at`.
  bool followed_dot_at(cv::Point2d at, double scale) const;
};

}  // namespace rostro::tracking
