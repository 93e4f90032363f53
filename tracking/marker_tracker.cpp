#include "tracking/marker_tracker.hpp"

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
#include "tracking/face_prior.hpp"
#include "tracking/identify.hpp"
#include "tracking/lid_geometry.hpp"
#include "tracking/lk_pyramid.hpp"
#include "tracking/lower_lip_search.hpp"
#include "tracking/overlay.hpp"
#include "tracking/tag_alignment.hpp"

namespace rostro::tracking {

using namespace internal;  // the eyes' geometry and the lower lip's search

namespace {

// DotOptions::max_surround that no ring reaches: no dark-ring test.
constexpr double kNoSurroundTest = 1e9;

cv::Point2d mean_of(const std::array<cv::Point2d, 4>& c) {
  return (c[0] + c[1] + c[2] + c[3]) * 0.25;
}

cv::Rect box_around(const std::array<cv::Point2d, 4>& corners, double margin) {
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

DotRole role_of(const FeaturePointId& fp) {
  constexpr int kLeftOuterCorner = 7, kRightOuterCorner = 12;
  if (is_lid_point(fp)) return DotRole::Lid;
  if (is_inner_eye_corner(fp)) return DotRole::InnerEyeCorner;
  if (is_eye_point(fp))
    return fp.index == kLeftOuterCorner || fp.index == kRightOuterCorner ? DotRole::OuterEyeCorner
                                                                         : DotRole::OtherEye;
  if (fp.group == 4 && (fp.index == 3 || fp.index == 4)) return DotRole::MidBrow;
  if (at_lower_lip(fp)) return DotRole::LowerLip;
  return DotRole::Plain;
}

bool on_chin(const FeaturePointId& fp) {
  return fp.group == 2 && (fp.index == 1 || fp.index >= 10);
}

bool at_eye(DotRole r) {
  return r == DotRole::Lid || r == DotRole::InnerEyeCorner || r == DotRole::OuterEyeCorner ||
         r == DotRole::OtherEye;
}

// Whether a dot lies among the face's dark round features, where a blob in a dark ring is one
// of them (the pupil in its iris, a nostril, a lid dot against its lashes seen from a brow
// dot): the eyes, the brows and the nose (TrackerOptions::surround_test_upper_face_only).
bool by_dark_features(const FeaturePointId& fp) {
  return fp.group == 3 || fp.group == 4 || fp.group == 9;
}

}  // namespace

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
  cv::Mat gray;          // this frame; a view of the caller's image when it is grey already
  cv::Mat gray_storage;  // conversion buffer for colour input, reused frame to frame
  // The LK pyramids cover only the region the markers occupy (plus room for motion), not the
  // whole frame: at 1280x720 a fifth to a half of the pixels. LK needs both pyramids of one
  // size, so the region keeps its size from frame to frame and only moves; it is resized
  // (the new frame's pyramid built twice) when the markers outgrow it or shrink well inside.
  LkPyramid previous_pyramid, pyramid;
  cv::Rect previous_region, region;

  Impl(MarkerLayout l, TrackerOptions o)
      : layout(std::move(l)),
        options(validated(o)),
        full_detector(with_layout_families(options.tags)),
        window_detector(window_options(with_layout_families(options.tags))),
        threads(options.threads > 0 ? options.threads : std::max(1, cv::getNumberOfCPUs())) {
    for (const MarkerSpec& m : layout.markers) {
      MarkerState s;
      s.spec = &m;
      states.push_back(s);
      aligners.push_back(m.is_tag()
                             ? std::make_optional<TagAligner>(apriltag_image(m.family, m.tag_id),
                                                              apriltag_black_width(m.family))
                             : std::nullopt);
    }
    std::vector<FeaturePointId> points;
    for (const MarkerState& s : states) points.push_back(s.spec->feature_point);
    lids = LidGeometry(points);
    for (const FeaturePointId& fp : points) roles.push_back(role_of(fp));
    options.dots.polarity = layout.polarity;
    centroid_dots = options.dots;
    centroid_dots.edge_fit = false;
    lower_face_dots = options.dots;
    lower_face_centroid_dots = centroid_dots;
    if (options.surround_test_upper_face_only)
      lower_face_dots.max_surround = lower_face_centroid_dots.max_surround = kNoSurroundTest;
    inner_corner_dots = options.dots;
    inner_corner_dots.raise_share_for_roundness |= options.eyes.inner_corners_raise_share;
    // The inner corners' centre from the raised share's blob (its centroid, then the symmetric
    // centre, EyeOptions::inner_corners_symmetric_centre), not the edge fit: the edge fit's
    // rays there run along the slit's corner line and the lashes, and its centre moved with
    // the expression (Xface fear at 1280x720: 0.32-0.41 px frame-to-frame spread in x against
    // 0.14-0.18 for the centroid, which went into the head pose: pitch 5.8 -> 2.7 % of range).
    inner_corner_dots.edge_fit = false;
    inner_corner_dots.symmetric_centre = options.eyes.inner_corners_symmetric_centre;
    inner_corner_dots_large = inner_corner_dots;
    inner_corner_dots_large.max_elongation =
        std::max(options.dots.max_elongation, options.eyes.inner_corner_max_elongation_large);
    for (size_t i = 0; i < states.size(); ++i) {
      const DotRole r = roles[i];
      const bool edge_fit =
          tracking::at_eye(r) ||
          (r == DotRole::MidBrow ? options.brows.edge_fit_mid_brows : options.edge_fit_elsewhere);
      const bool upper_face = by_dark_features(points[i]);
      const DotOptions* plain = edge_fit
                                    ? (upper_face ? &options.dots : &lower_face_dots)
                                    : (upper_face ? &centroid_dots : &lower_face_centroid_dots);
      const bool inner_corner = r == DotRole::InnerEyeCorner;
      measured_with[0].push_back(inner_corner ? &inner_corner_dots : plain);
      measured_with[1].push_back(inner_corner ? &inner_corner_dots_large : plain);
    }
  }

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

  AprilTagOptions with_layout_families(AprilTagOptions o) const {
    auto families = layout.tag_families();
    if (!families.empty()) o.families = families;
    return o;
  }
  static AprilTagOptions window_options(AprilTagOptions o) {
    o.decimation = 1;
    o.refine_edges = true;
    o.threads = 1;
    return o;
  }

  // Colour input is converted to grey only where the tracker looks (the pyramid region and
  // the windows it searches), not over the whole frame: at 1280x720 the full conversion
  // costs about 0.3 ms, a fifth of a frame's tracking.
  const cv::Mat* colour = nullptr;
  std::vector<cv::Rect> converted;

  void to_gray(const cv::Mat& image) {
    converted.clear();
    if (image.channels() == 3 || image.channels() == 4) {
      colour = &image;
      gray_storage.create(image.size(), CV_8UC1);
      gray = gray_storage;
    } else {
      // Only read during this call: the pyramid copies what it keeps (no reuse of the input).
      colour = nullptr;
      gray = image;
    }
  }

  // Makes sure the grey image holds this frame's pixels inside `r`.
  void ensure_gray(cv::Rect r) {
    if (!colour) return;
    r &= cv::Rect(0, 0, gray.cols, gray.rows);
    if (r.empty()) return;
    for (const cv::Rect& c : converted)
      if ((r & c) == r) return;
    cv::Mat out = gray(r);
    cv::cvtColor((*colour)(r), out,
                 colour->channels() == 3 ? cv::COLOR_BGR2GRAY : cv::COLOR_BGRA2GRAY);
    converted.push_back(r);
  }
  void ensure_gray_around(cv::Point2d p, double radius) {
    if (!colour) return;
    const int half = static_cast<int>(std::ceil(radius + options.dots.max_diameter_px / 2 + 3));
    ensure_gray({static_cast<int>(std::lround(p.x)) - half,
                 static_cast<int>(std::lround(p.y)) - half, 2 * half + 1, 2 * half + 1});
  }

  // ---- the region the pyramids cover ----------------------------------------------------

  // The markers' bounding box (last known places, tag corners included) with room for a
  // frame's motion and the LK window at the top level.
  cv::Rect needed_region() const {
    double x0 = 1e18, y0 = 1e18, x1 = -1e18, y1 = -1e18;
    auto add = [&](cv::Point2d p) {
      x0 = std::min(x0, p.x), y0 = std::min(y0, p.y), x1 = std::max(x1, p.x),
      y1 = std::max(y1, p.y);
    };
    for (size_t i = 0; i < states.size(); ++i) {
      const MarkerState& s = states[i];
      if (s.spec->is_tag())
        for (const auto& c : s.valid ? s.corners : reference_corners[i]) add(c);
      else
        add(s.valid ? s.position : reference[i]);
    }
    const double margin = options.region_margin_px * px +
                          0.5 * lk_window() * static_cast<double>(1 << options.lk_levels);
    const cv::Rect r(cv::Point(static_cast<int>(std::floor(x0 - margin)),
                               static_cast<int>(std::floor(y0 - margin))),
                     cv::Point(static_cast<int>(std::ceil(x1 + margin)),
                               static_cast<int>(std::ceil(y1 + margin))));
    return r & cv::Rect(0, 0, gray.cols, gray.rows);
  }

  // A region of `size` centred on `want`, inside the image.
  cv::Rect placed(cv::Size size, const cv::Rect& want) const {
    size.width = std::min(size.width, gray.cols), size.height = std::min(size.height, gray.rows);
    const int cx = want.x + want.width / 2, cy = want.y + want.height / 2;
    const int x = std::clamp(cx - size.width / 2, 0, gray.cols - size.width);
    const int y = std::clamp(cy - size.height / 2, 0, gray.rows - size.height);
    return {x, y, size.width, size.height};
  }

  // The size a region should get when it is (re)sized: the need plus a tenth each way, so
  // that ordinary motion and expressions do not resize it again.
  cv::Size grown(const cv::Rect& need) const {
    return {std::min(gray.cols, need.width + need.width / 5 + 16),
            std::min(gray.rows, need.height + need.height / 5 + 16)};
  }

  bool fits(cv::Size size, const cv::Rect& need) const {
    const bool holds = (size.width >= need.width || size.width == gray.cols) &&
                       (size.height >= need.height || size.height == gray.rows);
    const cv::Size ideal = grown(need);
    const bool not_too_big = static_cast<double>(size.area()) <= 1.5 * ideal.area();
    return holds && not_too_big;
  }

  void build_pyramid(const cv::Rect& r, LkPyramid& out) const {
    out.build(gray(r), {lk_window(), lk_window()}, options.lk_levels);
  }

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

  // 6. (TrackerOptions::second_look_after.) The frame named afresh; where the naming is
  //    confident, about as sure as the start's (IdentificationConfidence::margin, within
  //    kMarginNoise), explains about as many dots (within kMatchedNoise) and moves a followed name
  //    onto another dot, the take starts again here on that naming. Where it only puts names a
  //    dot's width or so from where they are followed, each of those names goes to whichever of the
  //    two dots looks more like a dot (placed_by_look). A naming too unsure to judge by is tried
  //    again second_look_after frames later, up to second_look_tries times; such a later look
  //    renames only what the confident look before it renamed: two namings against one, however
  //    sure the start's was.
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
  // False when the naming was too unsure to judge the followed names by.
  bool second_look(long frame) {
    ensure_gray({0, 0, gray.cols, gray.rows});
    const Identification id = name_frame(detect_all_tags());
    if (!id.confidence.confident) {
      moved_before.clear();
      return false;
    }
    std::vector<std::string> moved;
    for (size_t i = 0; i < states.size(); ++i) {
      const auto named = id.dots.find(states[i].spec->id);
      if (!states[i].valid || named == id.dots.end()) continue;
      if (cv::norm(named->second.center - states[i].position) > 0.5 * spacing[i] * face_scale)
        moved.push_back(states[i].spec->id);
    }
    const bool confirmed = !moved.empty() && moved == moved_before;
    moved_before = moved;
    // (A start on a frame a fading blur still smears is sure for a wrong reason:
    // TrackerOptions::second_look_tries.)
    const bool as_sure = id.confidence.margin + kMarginNoise >= identification.margin &&
                         id.confidence.matched + kMatchedNoise >= identification.matched;
    if (moved.empty()) {
      if (!as_sure) return false;
      const std::vector<std::string> placed = placed_by_look(id);
      if (!placed.empty())
        note = "second look: " + std::to_string(placed.size()) +
               " names placed by their dots' look (" + first_and_more(placed) + ")";
      return true;
    }
    // The first look renames alone; a look after an unjudged one only as the one before it did
    // (a dim face's third look, as sure as the start, moved the lower lip's names onto their
    // neighbours' dots).
    if (!confirmed && !(as_sure && looks == 1)) return false;
    if (!enough(id.dots.size() + id.tags.size())) return true;
    begin(adopt(id));
    started_at = frame;
    note = "identified again (" + std::to_string(moved.size()) +
           " names moved: " + first_and_more(moved) + "), " + describe(identification);
    return true;
  }

  // "a" or "a, ...": a list of names in a frame's note.
  static std::string first_and_more(const std::vector<std::string>& names) {
    return names.front() + (names.size() > 1 ? ", ..." : "");
  }

  // A dot worn on the skin is round and has no dark ring around it; the face's own dark
  // features beside the dots (the eye's corner, the pupil in its iris, the lip corner) are
  // elongated or lie in darker surroundings. Zero for a clean dot, larger the less like one.
  static double unlike_a_dot(const Dot& d) { return d.surround + (d.elongation - 1); }

  // The names the second look's naming puts more than a dot's width from where they are
  // followed (or finds while they are lost), each placed on the naming's dot where that looks
  // more like a dot than the one followed, and no other followed dot is on it. Which of the two
  // is the dot cannot be told by where they lie: LK carries an eye dot onto the eye's corner
  // while a blur fades (the followed one is wrong), and the landmarks that place the names lie
  // toward the eyes' dark features on the rendered head (the naming is wrong).
  std::vector<std::string> placed_by_look(const Identification& id) {
    std::vector<std::string> placed;
    for (size_t i = 0; i < states.size(); ++i) {
      MarkerState& s = states[i];
      const auto named = id.dots.find(s.spec->id);
      if (s.spec->is_tag() || named == id.dots.end()) continue;
      const double width = std::max(reference_diameter[i], 2.0);
      if (s.valid && cv::norm(named->second.center - s.position) <= width) continue;
      const std::optional<Dot> fresh = refine_dot(gray, named->second.center, 2, dot_options(i));
      if (!fresh) continue;
      if (s.valid) {
        const std::optional<Dot> followed = refine_dot(gray, s.position, 2, dot_options(i));
        if (followed && unlike_a_dot(*followed) <= unlike_a_dot(*fresh)) continue;
      }
      bool taken = false;
      for (size_t j = 0; j < states.size(); ++j)
        taken |= j != i && states[j].valid && !states[j].spec->is_tag() &&
                 cv::norm(states[j].position - fresh->center) < width;
      if (taken) continue;
      found_on(i, *fresh);
      unconfirmed.insert(i);  // named by one frame's naming, as at the start
      placed.push_back(s.spec->id);
    }
    return placed;
  }

  std::vector<TagDetection> detect_all_tags() {
    return layout.tag_count() > 0 ? full_detector.detect(gray) : std::vector<TagDetection>{};
  }

  void start() {
    ensure_gray({0, 0, gray.cols, gray.rows});
    const std::vector<TagDetection> tags = timed("detect_tags", [&] { return detect_all_tags(); });
    const std::vector<std::pair<cv::Point2d, cv::Point2d>> known = timed("identify", [&] {
      return start_positions.empty() ? adopt(name_frame(tags)) : find_at_start_positions(tags);
    });
    const bool doubtful = start_positions.empty() && !identification.confident;
    if (doubtful || !begin(known))
      for (MarkerState& s : states) s.valid = false, s.lost_reason = LostReason::Unidentified;
  }

  bool enough(size_t placed) const {
    return static_cast<int>(placed) >= std::max(3, options.min_identified);
  }

  // Tracking begun from the markers placed (frontal layout position -> image position); false,
  // nothing changed but the states' places, with too few of them.
  bool begin(const std::vector<std::pair<cv::Point2d, cv::Point2d>>& known) {
    if (!enough(known.size())) return false;
    place_unseen(known);
    unconfirmed.clear(), called_otherwise.clear();
    for (size_t i = 0; i < states.size(); ++i)
      if (states[i].valid && !states[i].spec->is_tag()) unconfirmed.insert(i);
    if (options.align_tags)
      timed("align_tags", [&] {
        for (size_t i = 0; i < states.size(); ++i)
          if (states[i].valid && aligners[i]) align_tag(i, states[i].corners);
      });
    scale_to_dots(measure_seen());
    measure_spacing();
    started = true;
    return true;
  }

  // The markers found where the file of starting positions puts them (within a few pixels), as
  // frontal layout position -> image position.
  std::vector<std::pair<cv::Point2d, cv::Point2d>> find_at_start_positions(
      const std::vector<TagDetection>& tags) {
    std::vector<std::pair<cv::Point2d, cv::Point2d>> known;
    expected_start.clear();
    for (MarkerState& s : states) {
      s.valid = false;
      auto it = start_positions.find(s.spec->id);
      if (it == start_positions.end()) continue;
      if (s.spec->is_tag()) {
        for (const TagDetection& t : tags)
          if (t.marker_id() == s.spec->id && cv::norm(t.center - it->second) < 20)
            s.valid = true, s.corners = t.corners, s.position = t.center;
      } else if (auto d = refine_dot(gray, it->second, 3,
                                     dot_options(static_cast<size_t>(&s - states.data())))) {
        s.valid = true, s.position = d->center;
      }
      if (s.valid) known.push_back({s.spec->frontal(), s.position});
    }
    return known;
  }

  // Every dot and tag in the frame, identified (identify.hpp).
  // The dots found on the whole frame named (identify.hpp). With a landmark model at hand,
  // the layout's arrangement alone is not enough to start on: on a real face it names the
  // lower face a row off (the dots of a smile, a long jaw). The face is found on a later frame
  // (it entered, turned back, came into focus).
  Identification name_frame(const std::vector<TagDetection>& tags) {
    const auto expected = expected_places(tags);
    Identification id = identify_markers(layout, detect_dots(gray, centroid_dots), tags,
                                         options.identification, expected);
    if (face_prior.available() && !id.confidence.face_model && id.confidence.confident) {
      id.confidence.confident = false;
      id.confidence.doubt = expected.empty() ? "the landmark model found no face"
                                             : "the face's landmarks disagree with the tags";
    }
    return id;
  }

  // The markers placed where `id` names them, as frontal layout position -> image position.
  std::vector<std::pair<cv::Point2d, cv::Point2d>> adopt(const Identification& id) {
    std::vector<std::pair<cv::Point2d, cv::Point2d>> known;
    identification = id.confidence;
    expected_start = id.places;
    for (MarkerState& s : states) {
      s.valid = false;
      if (s.spec->is_tag()) {
        auto it = id.tags.find(s.spec->id);
        if (it != id.tags.end())
          s.valid = true, s.corners = it->second.corners, s.position = it->second.center;
      } else {
        auto it = id.dots.find(s.spec->id);
        if (it != id.dots.end()) s.valid = true, s.position = it->second.center;
      }
      if (s.valid) known.push_back({s.spec->frontal(), s.position});
    }
    return known;
  }

  // Where dlib's landmarks put the layout's dots on the face the tags are on (face_prior.hpp).
  std::map<std::string, cv::Point2d> expected_places(const std::vector<TagDetection>& tags) {
    return face_prior.expected(gray, layout, layout_to_image(tags));
  }

  // The layout's frontal millimetres to pixels, as the tags read place it.
  std::optional<cv::Matx23d> layout_to_image(const std::vector<TagDetection>& tags) const {
    std::vector<cv::Point2d> from, to;
    for (const MarkerSpec& m : layout.markers)
      for (const TagDetection& t : tags)
        if (m.is_tag() && t.family == m.family && t.id == m.tag_id) {
          const auto corners = m.tag_corners_frontal();
          for (int k = 0; k < 4; ++k) from.push_back(corners[k]), to.push_back(t.corners[k]);
        }
    if (from.empty()) return std::nullopt;
    const cv::Mat s = cv::estimateAffinePartial2D(from, to, cv::noArray(), cv::LMEDS);
    if (s.empty()) return std::nullopt;
    return cv::Matx23d(s);
  }

  // Where the unseen markers should be: the layout mapped by the seen ones.
  void place_unseen(const std::vector<std::pair<cv::Point2d, cv::Point2d>>& known) {
    std::vector<cv::Point2d> from, to;
    for (const auto& [f, t] : known) from.push_back(f), to.push_back(t);
    cv::Matx23d mapping(cv::estimateAffine2D(from, to, cv::noArray(), cv::LMEDS));
    const size_t n = states.size();
    reference.assign(n, {});
    reference_seen.assign(n, false);
    reference_corners.assign(n, {});
    for (size_t i = 0; i < n; ++i) {
      MarkerState& s = states[i];
      if (s.valid) continue;
      // The identification's place for an unseen dot follows this face's shape; the mapping
      // the layout's average one.
      const auto place = expected_start.find(s.spec->id);
      reference[i] =
          place != expected_start.end() ? place->second : apply(mapping, s.spec->frontal());
      if (s.spec->is_tag()) {
        auto c = s.spec->tag_corners_frontal();
        for (int k = 0; k < 4; ++k) reference_corners[i][k] = apply(mapping, c[k]);
      }
    }
  }

  // The seen markers' start positions, and the seen dots' contrast and size (returned: the
  // contrasts and sizes of the dots measured, in marker order).
  std::pair<std::vector<double>, std::vector<double>> measure_seen() {
    const size_t n = states.size();
    std::vector<double> contrasts, diameters;
    reference_contrast.assign(n, 0);
    reference_diameter.assign(n, 0);
    usual_look.assign(n, 0);
    for (size_t i = 0; i < n; ++i) {
      MarkerState& s = states[i];
      s.quality = s.valid ? 1 : 0;
      s.lost_frames = s.valid ? 0 : 1;
      s.lost_reason = s.valid ? LostReason::None : LostReason::Unidentified;
      if (!s.valid) continue;
      reference[i] = s.position;
      reference_seen[i] = true;
      reference_corners[i] = s.corners;
      if (s.spec->is_tag()) continue;
      // An eye dot is identified by its centroid alone, beside the slit's corner line
      // even on a weak blob between the two (1280x720: 2.9 px off): measured again, as it
      // will be followed, from the strongest point within a few pixels.
      if (at_eye(i))
        if (auto d = refine_dot(gray, s.position, 3, dot_options(i)))
          reference[i] = s.position = d->center;
      if (auto d = refine_dot(gray, s.position, 1.5, dot_options(i))) {
        reference_contrast[i] = d->contrast, reference_diameter[i] = d->diameter;
        usual_look[i] = unlike_a_dot(*d);
        contrasts.push_back(d->contrast), diameters.push_back(d->diameter);
      }
    }
    return {contrasts, diameters};
  }

  // The pixel-valued options scaled to the dots' typical size (px, large_dots); the dots not
  // measured at the start take the typical contrast and size.
  void scale_to_dots(const std::pair<std::vector<double>, std::vector<double>>& measured) {
    const auto& [contrasts, diameters] = measured;
    auto median = [](std::vector<double> v) {
      if (v.empty()) return 0.0;
      std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
      return v[v.size() / 2];
    };
    const double typical_contrast = median(contrasts), typical_diameter = median(diameters);
    std::vector<double> looks;
    for (size_t i = 0; i < states.size(); ++i)
      if (reference_contrast[i] > 0) looks.push_back(usual_look[i]);
    const double typical_look = median(looks);
    px = std::max(1.0, typical_diameter / options.reference_dot_px);
    large_dots = typical_diameter >= options.reference_dot_px;
    for (size_t i = 0; i < states.size(); ++i)
      if (!states[i].spec->is_tag() && reference_contrast[i] <= 0)
        reference_contrast[i] = typical_contrast, reference_diameter[i] = typical_diameter,
        usual_look[i] = typical_look;
    recent_diameter = reference_diameter;
    recent_elongation.assign(states.size(), 1);
    face_scale = 1;
  }

  // Each marker's nearest other marker at the start.
  void measure_spacing() {
    const size_t n = states.size();
    spacing.assign(n, std::numeric_limits<double>::max());
    for (size_t i = 0; i < n; ++i)
      for (size_t j = 0; j < n; ++j)
        if (i != j) spacing[i] = std::min(spacing[i], cv::norm(reference[i] - reference[j]));
  }

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
  double max_eye_snap() const { return options.eyes.max_eye_snap * px; }
  int lk_window() const {
    return static_cast<int>(std::lround(options.lk_window * std::sqrt(px))) | 1;
  }

  // The first check dot d fails as marker i (None: it passes). Any dot may be at most twice its
  // start size; a followed eye dot too: blurred it grows as much as merged, and where it was
  // dropped for that it came back on a neighbour (docs/accuracy.md, the photo scenes' blur).
  LostReason dot_check(size_t i, const Dot& d, bool followed) const {
    if (is_lid(i) && d.elongation > options.eyes.max_lid_elongation)
      return LostReason::LidElongation;
    if (is_lid(i) && d.surround > options.eyes.max_lid_surround) return LostReason::LidSurround;
    if (!(d.contrast >= options.min_contrast_ratio * reference_contrast[i]))
      return LostReason::Contrast;
    if (!(d.diameter >= 0.5 * reference_diameter[i])) return LostReason::Shrunk;
    if (!(d.diameter <= (at_eye(i) && !followed ? largest_found(i) : 2.0 * reference_diameter[i])))
      return LostReason::Growth;
    return LostReason::None;
  }
  // At the eye a blob found where a lost dot was may be the dot merged with something dark
  // beside it: the pupil beside a lid dot as the lid closes, the other lid's dot in a blink.
  // Its centre is the pair's and neither marker's, so it is not taken. The dot may have turned
  // toward the camera meanwhile, so after a long loss it may be a little larger than it was
  // then (`recent_diameter`, its last sizes measured, smoothed) or at the start, not as large
  // as two dots (after a short one, than it was then, when it was seen edge-on: merged with a
  // dark neighbour it is about its start size). The largest blob eye dot i is found again on.
  double largest_found(size_t i) const {
    const double was = recent_diameter[i] > 0 ? recent_diameter[i] : reference_diameter[i];
    // (EyeOptions::eye_size_memory_frames: an eye dot last seen edge-on and lost a short
    // while keeps its own size.)
    const bool edge_on_lately = states[i].lost_frames < options.eyes.eye_size_memory_frames &&
                                recent_elongation[i] >= options.eyes.edge_on_elongation;
    const double grown_from =
        edge_on_lately ? was : std::max(was, reference_diameter[i] * face_scale);
    return options.eyes.max_dot_growth_found * grown_from;
  }
  bool dot_passes(size_t i, const Dot& d, bool followed) const {
    return dot_check(i, d, followed) == LostReason::None;
  }
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
  double face_scale = 1;                  // the face's size now over its size at the start
  std::vector<double> recent_diameter;    // per dot, smoothed over its last measurements
  std::vector<double> recent_elongation;  // per dot, when last measured
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
  bool failed_round_trip(const Flow& f, size_t k) const {
    return !f.status[k] || !f.status_back[k] || cv::norm(f.back[k] - f.before[k]) > max_fb_error();
  }
  // Each valid tag's corners where LK moved them, and whether all four made the round trip.
  struct TagGuesses {
    std::vector<std::array<cv::Point2d, 4>> corners;
    std::vector<bool> held;
  };

  void follow() {
    Flow flow = timed("lk_round_trip", [&] { return lk_round_trip(); });
    const TagGuesses tags = timed("tag_corner_guesses", [&] { return tag_corner_guesses(flow); });
    timed("snap_dots", [&] { snap_dots(flow); });
    timed("follow_tags", [&] { follow_tags(flow, tags); });
    timed("drop_jumped", [&] { drop_jumped(flow); });
    timed("drop_coincident", [&] { drop_coincident(); });
    timed("drop_off_lid_band", [&] { drop_off_lid_band(); });
    timed("reacquire_lost", [&] { reacquire_lost(flow); });
  }

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
  void check_identities() {
    if (unconfirmed.empty()) return;
    std::vector<Dot> places;
    std::vector<size_t> owner;
    std::vector<TagDetection> tags;
    for (size_t i = 0; i < states.size(); ++i) {
      const MarkerState& s = states[i];
      if (!s.valid) continue;
      if (s.spec->is_tag()) {
        TagDetection t;
        t.family = s.spec->family, t.id = s.spec->tag_id;
        t.corners = s.corners, t.center = s.position;
        tags.push_back(t);
      } else {
        Dot d;
        d.center = s.position, d.diameter = reference_diameter[i];
        places.push_back(d), owner.push_back(i);
      }
    }
    if (tags.empty()) return;
    const Identification id =
        identify_markers(layout, places, tags, options.identification, face_places(tags));
    if (!id.confidence.confident || (face_prior.available() && !id.confidence.face_model)) return;
    // Each followed dot's name in the naming; a dot it leaves out is no evidence.
    std::map<std::string, std::string> called;
    for (size_t k = 0; k < places.size(); ++k)
      for (const auto& [name, dot] : id.dots)
        if (dot.center == places[k].center) called[states[owner[k]].spec->id] = name;
    auto index_of = [&](const std::string& name) {
      const MarkerSpec* spec = layout.find(name);
      return spec != nullptr ? static_cast<size_t>(spec - layout.markers.data()) : states.size();
    };
    // The calls that hold: decisive and the same as on the last check.
    std::map<size_t, size_t> calls;               // state index -> the index of its new name
    std::map<std::string, std::string> misnamed;  // this check's calls, for the next one
    for (const auto& [own, name] : called) {
      const size_t from = index_of(own), to = index_of(name);
      if (!unconfirmed.count(from)) continue;  // LK has followed it since a check confirmed it
      const auto own_place = id.places.find(own);
      if (own_place == id.places.end()) continue;
      const cv::Point2d at = states[from].position;
      // The place of the name nearest the dot but the one under test.
      auto nearest_but = [&](const std::string& skip) {
        double best = std::numeric_limits<double>::max();
        for (const auto& [other, place] : id.places)
          if (other != skip) best = std::min(best, cv::norm(at - place));
        return best;
      };
      if (name == own) {
        // Confirmed: decisively nearer its own place than any other name's.
        if (cv::norm(at - own_place->second) <= kDecisive * nearest_but(own))
          unconfirmed.erase(from);
        continue;
      }
      if (to == states.size() || states[to].spec->is_tag()) continue;
      // Decisively nearer the other name's place than its own: where the two are about as
      // near (a blink brings the lids together, blur smears the eye) the naming guesses.
      const auto other_place = id.places.find(name);
      if (other_place == id.places.end()) continue;
      if (cv::norm(at - other_place->second) > kDecisive * cv::norm(at - own_place->second))
        continue;
      misnamed[own] = name;
      // A face deforming beyond the arrangements the naming knows (a mouth wide open) fools
      // it for a moment; a wrong name stays. So the call must hold on two checks in a row.
      const auto before = called_otherwise.find(own);
      if (before != called_otherwise.end() && before->second == name) calls[from] = to;
    }
    called_otherwise = std::move(misnamed);
    rename(moving_together(calls));
  }

  // The calls (state index -> the index of its new name) that can be followed: a dot takes a
  // name no followed dot holds, or one whose holder takes another in turn (a chain), or the
  // dots of a ring each take the next one's name. A chain ending in a name its holder keeps
  // stays as it is.
  std::vector<std::pair<size_t, size_t>> moving_together(const std::map<size_t, size_t>& calls) {
    std::set<size_t> moving;
    for (bool grew = true; grew;) {
      grew = false;
      for (const auto& [from, to] : calls)
        if (!moving.count(from) && (!states[to].valid || moving.count(to)))
          moving.insert(from), grew = true;
    }
    for (const auto& [from, to] : calls) {
      if (moving.count(from)) continue;
      std::vector<size_t> ring{from};
      for (size_t at = to; at != from;) {
        const auto next = calls.find(at);
        if (next == calls.end() || moving.count(at) ||
            std::find(ring.begin(), ring.end(), at) != ring.end()) {
          ring.clear();
          break;
        }
        ring.push_back(at), at = next->second;
      }
      moving.insert(ring.begin(), ring.end());
    }
    std::vector<std::pair<size_t, size_t>> moves;
    for (size_t from : moving) moves.push_back({from, calls.at(from)});
    return moves;
  }

  // Each (from, to) dot takes the name `to`; a name left behind is lost (LostReason::Identity),
  // and the frame reports the renaming.
  void rename(const std::vector<std::pair<size_t, size_t>>& moves) {
    if (moves.empty()) return;
    const std::vector<MarkerState> before = states;
    for (const auto& [from, to] : moves) states[from].valid = false;
    note = "identities checked: renamed";
    for (const auto& [from, to] : moves) {
      MarkerState& s = states[to];
      s.valid = true, s.position = before[from].position, s.quality = before[from].quality;
      s.lost_reason = LostReason::None;
      note += " " + before[from].spec->id + " -> " + s.spec->id;
    }
    for (const auto& [from, to] : moves)
      if (!states[from].valid) states[from].lost_reason = LostReason::Identity;
  }

  // Layout dot id -> pixels where the landmark model puts the dots on the face the tags
  // place, fitted without searching the frame (face_prior.hpp) in the box the tags give it.
  // (Not the followed dots' box: dots under wrong names would place it.) Empty without a model.
  std::map<std::string, cv::Point2d> face_places(const std::vector<TagDetection>& tags) {
    if (!face_prior.available()) return {};
    const auto to_image = layout_to_image(tags);
    if (!to_image) return {};
    std::map<std::string, cv::Point2d> placed;
    for (const MarkerSpec& m : layout.markers)
      if (!m.is_tag()) placed[m.id] = apply(*to_image, m.frontal());
    const auto box = face_prior.placed_box(layout, placed);
    if (!box) return {};
    // The model reads the face around its box; the grey image is converted where needed.
    const double pad = 0.25 * box->width;
    ensure_gray(cv::Rect(cv::Point(static_cast<int>(box->x - pad), static_cast<int>(box->y - pad)),
                         cv::Point(static_cast<int>(box->br().x + pad) + 1,
                                   static_cast<int>(box->br().y + pad) + 1)));
    return face_prior.fitted(gray, layout, *box);
  }

  // 1. LK on the valid dots and the valid tags' corners, forward and back.
  Flow lk_round_trip() {
    Flow f;
    f.was_valid.resize(states.size());
    for (size_t i = 0; i < states.size(); ++i) {
      const MarkerState& s = states[i];
      f.was_valid[i] = s.valid;
      if (!s.valid) continue;
      if (s.spec->is_tag()) {
        for (const auto& c : s.corners) f.before.emplace_back(c), f.owner.push_back(i);
      } else {
        f.before.emplace_back(s.position), f.owner.push_back(i);
      }
    }
    if (f.before.empty()) return f;
    // (No error measure asked of LK: nothing reads it, and it costs a window's interpolation
    // per point.)
    const cv::Size window(lk_window(), lk_window());
    const cv::TermCriteria stop(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 20, 0.03);
    // Each pyramid has its own region: points go to its coordinates and back.
    const cv::Point2f from_tl(previous_region.tl()), to_tl(region.tl());
    std::vector<cv::Point2f> local_before(f.before.size());
    f.after.resize(f.before.size());
    for (size_t k = 0; k < f.before.size(); ++k)
      local_before[k] = f.before[k] - from_tl, f.after[k] = f.before[k] - to_tl;
    // Derivatives only where LK reads them: around the points it follows from each pyramid.
    previous_pyramid.derivatives(local_before);
    cv::calcOpticalFlowPyrLK(previous_pyramid.as_lk_input(), pyramid.as_lk_input(), local_before,
                             f.after, f.status, cv::noArray(), window, options.lk_levels, stop,
                             cv::OPTFLOW_USE_INITIAL_FLOW);
    f.back = local_before;
    f.status_back.assign(f.before.size(), 1);
    // The way back only for the dots when the tags are aligned to their patterns: a tag's
    // alignment checks it (follow_tags), and its corners are a quarter of LK's points.
    std::vector<size_t> back;  // the points LK takes back
    for (size_t k = 0; k < f.before.size(); ++k)
      if (!options.align_tags || !states[f.owner[k]].spec->is_tag()) back.push_back(k);
    std::vector<cv::Point2f> back_from(back.size()), back_to(back.size());
    for (size_t j = 0; j < back.size(); ++j)
      back_from[j] = f.after[back[j]], back_to[j] = local_before[back[j]];
    std::vector<uchar> back_status;
    pyramid.derivatives(back_from);
    cv::calcOpticalFlowPyrLK(pyramid.as_lk_input(), previous_pyramid.as_lk_input(), back_from,
                             back_to, back_status, cv::noArray(), window, options.lk_levels, stop,
                             cv::OPTFLOW_USE_INITIAL_FLOW);
    for (size_t j = 0; j < back.size(); ++j)
      f.back[back[j]] = back_to[j], f.status_back[back[j]] = back_status[j];
    for (size_t k = 0; k < f.before.size(); ++k) f.after[k] += to_tl, f.back[k] += from_tl;
    return f;
  }

  TagGuesses tag_corner_guesses(const Flow& f) const {
    TagGuesses g{std::vector<std::array<cv::Point2d, 4>>(states.size()),
                 std::vector<bool>(states.size(), true)};
    std::vector<int> count(states.size(), 0);
    for (size_t k = 0; k < f.before.size(); ++k) {
      const size_t i = f.owner[k];
      const MarkerState& s = states[i];
      if (!s.spec->is_tag()) continue;
      int& c = count[i];
      g.corners[i][c] = f.status[k] ? cv::Point2d(f.after[k]) : s.corners[c];
      if (failed_round_trip(f, k)) g.held[i] = false;
      ++c;
    }
    return g;
  }

  // 2. Each dot that made LK's round trip snapped to its measured centre, if that passes the
  //    checks; the others turn invalid.
  void snap_dots(const Flow& f) {
    // The dots that made LK's round trip are measured apart from one another (each reads only
    // the grey image around it) on TrackerOptions::threads threads, then judged and applied
    // in their order: the result does not depend on the thread count. Their grey windows are
    // filled first, serially, as the conversion writes to the one grey image.
    std::vector<size_t> to_measure;  // point indices
    for (size_t k = 0; k < f.before.size(); ++k) {
      MarkerState& s = states[f.owner[k]];
      if (s.spec->is_tag()) continue;
      s.valid = false;
      if (failed_round_trip(f, k)) {
        s.lost_reason = LostReason::RoundTrip;
        continue;
      }
      ensure_gray_around(cv::Point2d(f.after[k]), max_snap());
      to_measure.push_back(k);
    }
    std::vector<std::optional<Dot>> measured(f.before.size());
    for_each_in_parallel(to_measure.size(), [&](size_t m) {
      const size_t k = to_measure[m];
      measured[k] = refine_dot(gray, cv::Point2d(f.after[k]), max_snap(), dot_options(f.owner[k]));
    });
    for (const size_t k : to_measure) {
      const size_t i = f.owner[k];
      MarkerState& s = states[i];
      const double fb = cv::norm(f.back[k] - f.before[k]);
      const std::optional<Dot>& d = measured[k];
      if (!d) {
        s.lost_reason = LostReason::NoDot;
        continue;
      }
      const cv::Point2d lk(f.after[k]);
      const double snap = cv::norm(d->center - lk);
      s.lost_reason = snap > max_snap()                    ? LostReason::Snap
                      : at_eye(i) && snap > max_eye_snap() ? LostReason::EyeSnap
                                                           : dot_check(i, *d, true);
      if (s.lost_reason != LostReason::None) continue;
      s.valid = true;
      s.position = d->center;
      recent_diameter[i] = 0.7 * recent_diameter[i] + 0.3 * d->diameter;
      recent_elongation[i] = d->elongation;
      usual_look[i] = 0.8 * usual_look[i] + 0.2 * unlike_a_dot(*d);
      s.quality = std::clamp(d->contrast / reference_contrast[i], 0.0, 1.0) *
                  (1 - 0.5 * fb / max_fb_error());
    }
  }

  // 3. A tag is rigid: LK moves its corners, and its whole printed pattern aligned from there
  //    (TrackerOptions::align_tags) gives them; a tag the pattern does not fit there (a hand
  //    over part of it, LK gone astray) is re-detected near the moved corners, then aligned.
  //    Without the alignment, LK's corners are kept between detections (every few frames) as
  //    long as all four pass the round trip and the square keeps its size.
  void follow_tags(const Flow& f, const TagGuesses& g) {
    if (options.align_tags) {
      for (size_t i = 0; i < states.size(); ++i) {
        if (!states[i].spec->is_tag() || !f.was_valid[i]) continue;
        if (!align_tag(i, g.corners[i])) find_tag(i, g.corners[i]);
      }
      return;
    }
    const bool detect_tags = ++frames_since_tag_detection >= options.tag_redetect_every;
    if (detect_tags) frames_since_tag_detection = 0;
    for (size_t i = 0; i < states.size(); ++i) {
      if (!states[i].spec->is_tag() || !f.was_valid[i]) continue;
      if (!detect_tags && g.held[i] && keeps_shape(states[i].corners, g.corners[i])) {
        states[i].corners = g.corners[i];
        states[i].position = diagonal_crossing(g.corners[i]);
        continue;
      }
      find_tag(i, g.corners[i]);
    }
  }

  // Tag i's corners from its whole printed pattern (tag_alignment.hpp) aligned from `start`,
  // several times nearer than the square's edges that detection and LK give: the tags carry
  // the head's pose. False, the state untouched, when the pattern does not fit there.
  std::vector<std::optional<TagAligner>> aligners;  // per marker: tags only
  bool align_tag(size_t i, const std::array<cv::Point2d, 4>& start) {
    MarkerState& s = states[i];
    ensure_gray(box_around(start, 0.2 * cv::norm(start[0] - start[1]) + 2));
    const auto c = aligners[i]->align(gray, start);
    if (!c) return false;
    s.valid = true;
    s.corners = *c;
    s.position = diagonal_crossing(*c);
    return true;
  }

  // 4a. A dot must move roughly as its neighbours do: LK that slid onto another dot (a
  //     neighbour's, while its own was hidden) moves very differently from them.
  void drop_jumped(const Flow& f) {
    std::vector<cv::Point2d> moved(states.size());
    for (size_t k = 0; k < f.before.size(); ++k)
      if (!states[f.owner[k]].spec->is_tag())
        moved[f.owner[k]] = states[f.owner[k]].position - cv::Point2d(f.before[k]);
    std::vector<size_t> jumped;
    for (size_t i = 0; i < states.size(); ++i) {
      if (!states[i].valid || states[i].spec->is_tag() || !f.was_valid[i]) continue;
      // The lower lip by the jaw's dots while three of them were followed, else by any.
      std::vector<std::pair<double, size_t>> near;
      for (const bool apart : {true, false}) {
        near.clear();
        for (size_t j = 0; j < states.size(); ++j)
          if (j != i && states[j].valid && f.was_valid[j] && !states[j].spec->is_tag() &&
              !(apart && apart_from_lower_lip(i, j)))
            near.push_back({cv::norm(reference[j] - reference[i]), j});
        if (near.size() >= 3 || !at_lower_lip(i)) break;
      }
      if (near.size() < 3) continue;
      std::sort(near.begin(), near.end());
      if (near.size() > 6) near.resize(6);
      std::vector<double> xs, ys;
      for (const auto& [d, j] : near) xs.push_back(moved[j].x), ys.push_back(moved[j].y);
      std::nth_element(xs.begin(), xs.begin() + static_cast<long>(xs.size() / 2), xs.end());
      std::nth_element(ys.begin(), ys.begin() + static_cast<long>(ys.size() / 2), ys.end());
      const cv::Point2d typical(xs[xs.size() / 2], ys[ys.size() / 2]);
      if (cv::norm(moved[i] - typical) >
          std::max(options.max_relative_motion_px * px, options.max_relative_motion * spacing[i]))
        jumped.push_back(i);
    }
    for (size_t i : jumped) states[i].valid = false, states[i].lost_reason = LostReason::Jump;
  }

  // 4b. Two dots on one spot: neither can be trusted (an identity swap is worse than a gap).
  void drop_coincident() {
    for (size_t i = 0; i < states.size(); ++i)
      for (size_t j = i + 1; j < states.size(); ++j) {
        MarkerState &a = states[i], &b = states[j];
        if (!a.valid || !b.valid || a.spec->is_tag() || b.spec->is_tag()) continue;
        if (cv::norm(a.position - b.position) < 0.5 * std::max(reference_diameter[i], 2.0)) {
          a.valid = b.valid = false;
          a.lost_reason = b.lost_reason = LostReason::Coincident;
        }
      }
  }

  // 4c. A followed lid dot that left its band (in_its_lid_band) is not the lid's: a take
  //     starting in a squint names the brow's dot the upper lid's.
  void drop_off_lid_band() {
    for (size_t i = 0; i < states.size(); ++i)
      if (states[i].valid && is_lid(i) && !in_its_lid_band(i, states[i].position))
        states[i].valid = false, states[i].lost_reason = LostReason::LidBand;
  }

  // 5. Look again for the markers that are not valid, where their neighbours put them.
  void reacquire_lost(const Flow& f) {
    remember_last_seen(f.was_valid, f.before, f.owner);
    predict_lost();
    // With LowerLipOptions::with_the_jaw the jaw's dots last, once the dots they are placed by
    // (and the upper lip the lower lip's search stands on) are back.
    bool lower_lip_searched = false;
    auto one_by_one = [&](bool before_the_lower_lip) {
      for (size_t i = 0; i < states.size(); ++i)
        if (!states[i].valid && has_prediction[i] &&
            (options.lower_lip.with_the_jaw && !on_jaw(i)) == before_the_lower_lip &&
            !(lower_lip_searched && searched_with_lower_lip(i)))
          reacquire(i);
    };
    one_by_one(true);
    lower_lip_searched = options.lower_lip.together && reacquire_lower_lip();
    one_by_one(false);
  }
  int frames_since_tag_detection = 0;

  // Side lengths within 10% of the last ones: LK did not slide a corner along an edge.
  static bool keeps_shape(const std::array<cv::Point2d, 4>& was,
                          const std::array<cv::Point2d, 4>& now) {
    for (int k = 0; k < 4; ++k) {
      const double a = cv::norm(was[k] - was[(k + 1) % 4]), b = cv::norm(now[k] - now[(k + 1) % 4]);
      if (std::abs(a - b) > 0.1 * a + 0.5) return false;
    }
    return true;
  }

  // The centre of a square seen in perspective: where its diagonals cross (as libapriltag's
  // centre, the homography's image of the tag centre).
  static cv::Point2d diagonal_crossing(const std::array<cv::Point2d, 4>& c) {
    const cv::Point2d d1 = c[2] - c[0], d2 = c[3] - c[1], r = c[1] - c[0];
    const double den = d1.x * d2.y - d1.y * d2.x;
    if (std::abs(den) < 1e-9) return mean_of(c);
    const double t = (r.x * d2.y - r.y * d2.x) / den;
    return c[0] + t * d1;
  }

  // Tag i detected again in a window around `guess` (and aligned to its pattern, align_tags);
  // false, the tag invalid, when it is not there.
  bool find_tag(size_t i, const std::array<cv::Point2d, 4>& guess) {
    MarkerState& s = states[i];
    const double side = cv::norm(guess[0] - guess[1]);
    const cv::Rect roi = box_around(guess, options.tag_margin * side + 4);
    if (s.valid) s.lost_reason = LostReason::TagLost;  // unless found below
    s.valid = false;
    // Large tags are found as well at half resolution, for a quarter of the cost; the
    // corners are refined on the full image either way.
    const float decimation = side > options.tag_decimate_above_px ? 2.0f : 1.0f;
    ensure_gray(roi);
    for (const TagDetection& t : window_detector.detect(gray, roi, decimation)) {
      if (t.marker_id() != s.spec->id) continue;
      if (cv::norm(t.center - mean_of(guess)) > side) continue;
      s.valid = true;
      s.corners = t.corners;
      s.position = t.center;
      s.quality = std::clamp(t.decision_margin / 100.0, 0.0, 1.0);
      if (options.align_tags) align_tag(i, s.corners);  // keeps the detection's if it fails
      return true;
    }
    return false;
  }

  // Where each invalid marker should be: an affine fit of its nearest valid neighbours'
  // start positions to their current ones, checked against the fit of all valid markers.
  std::vector<cv::Matx23d> prediction_fit;
  std::vector<bool> has_prediction;
  std::vector<cv::Point2d> predicted;
  std::vector<bool> carried_now;  // predicted from where it was last seen (lids)

  cv::Point2d predicted_at(size_t i) const { return predicted[i]; }

  void predict_lost() {
    const size_t n = states.size();
    prediction_fit.assign(n, {});
    has_prediction.assign(n, false);
    predicted.assign(n, {});
    carried_now.assign(n, false);
    std::vector<cv::Point2d> from, to;
    for (size_t j = 0; j < n; ++j)
      if (states[j].valid) from.push_back(reference[j]), to.push_back(states[j].position);
    if (from.size() < 3) return;
    cv::Mat global_fit = cv::estimateAffine2D(from, to, cv::noArray(), cv::RANSAC, 3.0);
    if (global_fit.empty()) return;
    const cv::Matx23d global(global_fit);
    const double global_scale = scale_of(global);
    face_scale = global_scale;
    for (size_t i = 0; i < n; ++i) {
      if (states[i].valid) continue;
      const bool by_jaw = placed_by_jaw(i);
      std::vector<std::pair<double, size_t>> near;
      for (size_t j = 0; j < n; ++j)
        if (states[j].valid && (!by_jaw || on_jaw(j)))
          near.push_back({cv::norm(reference[j] - reference[i]), j});
      std::sort(near.begin(), near.end());
      cv::Matx23d fit = by_jaw ? moved_with(global, near) : global;
      if (near.size() > 6) near.resize(6);
      if (!by_jaw && near.size() >= 4) {
        std::vector<cv::Point2d> f, t;
        for (const auto& [d, j] : near) f.push_back(reference[j]), t.push_back(states[j].position);
        cv::Mat local = cv::estimateAffine2D(f, t, cv::noArray(), cv::LMEDS);
        if (!local.empty()) {
          const cv::Matx23d l(local);
          double worst = 0;
          for (size_t k = 0; k < f.size(); ++k)
            worst = std::max(worst, cv::norm(apply(l, f[k]) - t[k]));
          const double ratio = scale_of(l) / global_scale;
          // A local fit that bends more than a face does is ignored.
          if (worst < std::max(2.0, 0.15 * spacing[i] * global_scale) && ratio > 0.7 && ratio < 1.4)
            fit = l;
        }
      }
      prediction_fit[i] = fit;
      const std::optional<cv::Point2d> carry = carried(i);
      predicted[i] = carry.value_or(apply(fit, reference[i]));
      carried_now[i] = carry.has_value();
      has_prediction[i] = true;
    }
  }

  // `global` moved by its miss at the nearest followed jaw dot (`jaw`, nearest first): the face's
  // fit follows the skull, and an open jaw carries the chin tens of pixels below where it puts
  // it, onto the lower lip's dot.
  cv::Matx23d moved_with(const cv::Matx23d& global,
                         const std::vector<std::pair<double, size_t>>& jaw) const {
    if (jaw.empty()) return global;
    const size_t j = jaw.front().second;
    const cv::Point2d miss = states[j].position - apply(global, reference[j]);
    cv::Matx23d moved = global;
    moved(0, 2) += miss.x, moved(1, 2) += miss.y;
    return moved;
  }

  // A lid dot lies at another depth than its neighbours, so under a head turn the start
  // positions' fit puts it pixels off (onto the eye corner, for a lower lid: 23 px in the
  // closed loop's turns). While it is lost it is carried instead from where it was last seen,
  // with the motion of the neighbours that were valid then (a few frames: nearly a shift).
  // Other dots are carried only in the frame they are lost in: there their last place is
  // still the best guess (Xface fear: the chin boss, lost as the hidden lower-lip dot came
  // back into view 14 px above it, was looked for where the start positions' fit put it, on
  // that lip dot, and the chin then took the chin boss's dot for the rest of the take). Carried
  // longer, a wrong identity at the start (the mouth clip's chin) is carried along rather than
  // corrected (suite mouth NME 0.0090 -> 0.0170), and the eye corners came back on their dot
  // merged with the lash line (3-7 px off).
  struct LastSeen {
    bool known = false;
    cv::Point2d position;
    std::vector<std::pair<size_t, cv::Point2d>> anchors;  // neighbour -> its position then
  };
  std::vector<LastSeen> last_seen;

  void remember_last_seen(const std::vector<bool>& was_valid,
                          const std::vector<cv::Point2f>& before,
                          const std::vector<size_t>& owner) {
    const size_t n = states.size();
    last_seen.resize(n);
    std::vector<cv::Point2d> then(n);
    for (size_t k = 0; k < before.size(); ++k) then[owner[k]] = cv::Point2d(before[k]);
    for (size_t i = 0; i < n; ++i) {
      if (states[i].valid) {
        last_seen[i].known = false;
        continue;
      }
      if (!was_valid[i] || states[i].spec->is_tag()) continue;
      LastSeen& l = last_seen[i];
      l.known = true;
      l.position = then[i];
      l.anchors.clear();
      std::vector<std::pair<double, size_t>> near;
      for (size_t j = 0; j < n; ++j)
        if (j != i && was_valid[j] && !states[j].spec->is_tag())
          near.push_back({cv::norm(reference[j] - reference[i]), j});
      std::sort(near.begin(), near.end());
      for (const auto& [d, j] : near) l.anchors.push_back({j, then[j]});
    }
  }

  std::optional<cv::Point2d> carried(size_t i) const {
    if (i >= last_seen.size() || !last_seen[i].known) return std::nullopt;
    if (!is_lid(i) && states[i].lost_frames > 0) return std::nullopt;
    const LastSeen& l = last_seen[i];
    std::vector<cv::Point2d> from, to;
    for (const auto& [j, at] : l.anchors) {
      if (!states[j].valid) continue;
      from.push_back(at), to.push_back(states[j].position);
      if (from.size() == 6) break;
    }
    if (from.empty()) return std::nullopt;
    if (from.size() >= 3) {
      cv::Mat m = cv::estimateAffinePartial2D(from, to, cv::noArray(), cv::LMEDS);
      if (!m.empty()) return apply(cv::Matx23d(m), l.position);
    }
    cv::Point2d shift(0, 0);
    for (size_t k = 0; k < from.size(); ++k) shift += to[k] - from[k];
    return l.position + shift * (1.0 / static_cast<double>(from.size()));
  }

  void reacquire(size_t i) {
    MarkerState& s = states[i];
    const cv::Matx23d& m = prediction_fit[i];
    const double scale = scale_of(m);
    if (s.spec->is_tag()) {
      std::array<cv::Point2d, 4> guess;
      for (int k = 0; k < 4; ++k) guess[k] = apply(m, reference_corners[i][k]);
      find_tag(i, guess);
      return;
    }
    const cv::Point2d expected = predicted_at(i);
    const double radius = options.search_fraction * spacing[i] * scale;
    ensure_gray_around(expected, radius);
    // Every dot near the expected place, nearest first: the strongest one there may be a dark
    // feature that is no marker (the pupil beside a lid dot) and fail the checks.
    // (Peaks too faint to pass dot_passes() are not even measured.)
    const double least = options.min_contrast_ratio * reference_contrast[i];
    for (const Dot& d : dots_near(gray, expected, radius, dot_options(i), 4, least)) {
      if (cv::norm(d.center - expected) > radius || !dot_passes(i, d, false)) continue;
      if (!belongs_to(i, d.center, scale)) continue;
      // A lid dot only where a lid can be: not on the brow's, the other lid's or a corner's dot.
      if (is_lid(i) && !in_its_lid_band(i, d.center)) continue;
      if (carried_now[i] && is_lid(i) && !along_its_lid_line(i, d.center, scale)) continue;
      // Last: it measures the blob again.
      if (!looks_like_itself(i, d)) continue;
      found_on(i, d);
      return;
    }
  }

  // TrackerOptions::found_look_allowance. The blob is measured again as a followed dot is
  // (from its own centre, within max_snap): found among the dots near a place, a dot merged
  // with a darker neighbour (a big brow dot against the eyebrow) measures as part of it.
  bool looks_like_itself(size_t i, const Dot& d) const {
    if (options.found_look_allowance < 0) return true;
    const std::optional<Dot> as_followed = refine_dot(gray, d.center, max_snap(), dot_options(i));
    const bool same_blob =
        as_followed && cv::norm(as_followed->center - d.center) <= 0.5 * d.diameter;
    return unlike_a_dot(same_blob ? *as_followed : d) <=
           usual_look[i] + options.found_look_allowance;
  }

  // Marker i found on dot d where LK did not follow it there: its look as measured now, its
  // quality its contrast against the start's, below a followed dot's.
  void found_on(size_t i, const Dot& d) {
    MarkerState& s = states[i];
    s.valid = true, s.position = d.center, s.lost_reason = LostReason::None;
    recent_diameter[i] = d.diameter, recent_elongation[i] = d.elongation;
    s.quality = 0.9 * std::clamp(d.contrast / reference_contrast[i], 0.0, 1.0);
    if (options.start_place_when_found && !reference_seen[i]) start_where_found(i);
  }

  // TrackerOptions::start_place_when_found: marker i, found, takes the start place that the fit
  // it was looked for by (predict_lost: its neighbours' motion since the start) takes its dot
  // back to. The spacings stay the start's: taken again, the chin boss's shrank with the chin's
  // new place and its search radius with it (the marker suite's low light: 33 -> 80 lost frames).
  void start_where_found(size_t i) {
    if (i >= has_prediction.size() || !has_prediction[i]) return;
    cv::Matx23d back;
    cv::invertAffineTransform(prediction_fit[i], back);
    reference[i] = apply(back, states[i].position);
    reference_seen[i] = true;
  }

  // A lid carried from where it was last seen moves up and down with the lid meanwhile, but
  // hardly sideways: a dot well to the side of where it is carried is an eye corner's.
  bool along_its_lid_line(size_t i, cv::Point2d at, double scale) const {
    const std::optional<cv::Point2d> axis = lids.axis(i, reference, prediction_fit[i]);
    if (!axis) return true;
    return std::abs((at - predicted_at(i)).dot(*axis)) <=
           options.eyes.lid_sideways_fraction * spacing[i] * scale;
  }

  LidGeometry lids;  // each lid dot's eye corners (lid_geometry.hpp)

  // An upper-lid dot lies above its eye's corner line and a lower-lid dot below it, even in a
  // blink (the lids meet near the line, a fraction of a spacing off at most), and not much
  // farther from it than at the start (the brow is farther): a dot elsewhere is the other
  // lid's, the brow's or a corner's. Checked only while both corners are followed: a line
  // through predicted corners tilts too much under head turns to tell.
  bool in_its_lid_band(size_t i, cv::Point2d at) const {
    const auto& corners = lids.corners(i);
    if (!corners) return true;
    const auto [inner, outer] = *corners;
    if (!states[inner].valid || !states[outer].valid) return true;
    const auto offset = lids.offset_from_corner_line(i, reference, at, states[inner].position,
                                                     states[outer].position);
    if (!offset) return true;
    return offset->now >= -options.eyes.lid_overshoot_fraction * spacing[i] * face_scale &&
           offset->now <= options.eyes.lid_reach * offset->at_start * face_scale;
  }

  // ---- the lower lip (lower_lip_search.hpp) ---------------------------------------------

  bool at_lower_lip(size_t i) const { return roles[i] == DotRole::LowerLip; }
  // LowerLipOptions::with_the_jaw: the dots the jaw carries.
  bool on_jaw(size_t i) const { return at_lower_lip(i) || on_chin(states[i].spec->feature_point); }
  bool placed_by_jaw(size_t i) const { return options.lower_lip.with_the_jaw && on_jaw(i); }
  // The lower lip opens with the jaw by up to a spacing in a frame (Xface joy), unlike the
  // upper lip and the corners: its dots are no measure of how theirs should move
  // (LowerLipOptions::together), nor theirs of how its dots should (with_the_jaw: the jaw's
  // dots are).
  bool apart_from_lower_lip(size_t i, size_t j) const {
    if (at_lower_lip(i)) return options.lower_lip.with_the_jaw && !on_jaw(j);
    return options.lower_lip.together && at_lower_lip(j);
  }

  // A lower-lip dot not seen when tracking started has a start place that is the
  // identification's guess: the shape the together search matches is where the dots were
  // seen, so such a dot is looked for on its own, where its neighbours put it (the photo
  // scene with a hand: the three lower-lip dots unnamed at the start, found together with the
  // middle one's name on its neighbour's dot).
  bool searched_with_lower_lip(size_t i) const { return at_lower_lip(i) && reference_seen[i]; }

  // LowerLipOptions::together: the lower lip's lost dots found again together
  // (find_lower_lip). Returns whether the lower lip was searched so (the single-dot search
  // then skips its dots).
  bool reacquire_lower_lip() {
    LowerLipScene scene;
    for (size_t i = 0; i < states.size(); ++i) {
      const MarkerState& s = states[i];
      if (s.spec->is_tag()) continue;
      if (searched_with_lower_lip(i))
        scene.lower_lip.push_back(
            {i, reference[i], spacing[i], s.valid, s.position, !s.valid && has_prediction[i]});
      else if (!s.valid && has_prediction[i])
        scene.expected.push_back({i, predicted_at(i), spacing[i]});
      if (!s.valid) continue;
      if (at_upper_lip_or_corner(s.spec->feature_point))
        scene.upper_start.push_back(reference[i]), scene.upper_now.push_back(s.position);
      scene.followed.push_back({i, s.position, spacing[i]});
    }
    LowerLipSearch search;
    search.options = options.lower_lip;
    search.dots_near = [this](size_t k, cv::Point2d centre, double radius) {
      ensure_gray_around(centre, radius);
      const double least = options.min_contrast_ratio * reference_contrast[k];
      return dots_near(gray, centre, radius, dot_options(k), 4, least);
    };
    // Not asked the look (found_look_allowance): found together they are held to the lip's
    // shape already, and asked, the lower lip's dots beside the open mouth were left lost (the
    // closed loops, docs/accuracy.md).
    search.passes = [this](size_t k, const Dot& d) { return dot_passes(k, d, false); };
    const std::optional<std::vector<LowerLipFound>> found = find_lower_lip(scene, search);
    if (!found) return false;
    for (const LowerLipFound& f : *found) found_on(f.marker, f.dot);
    return true;
  }

  // A dot that belongs to a valid neighbour, or lies about as near another lost marker's
  // expected place as this one's (IdentificationOptions::unnamed_rival, as at the start), is
  // not marker i.
  bool belongs_to(size_t i, cv::Point2d at, double scale) const {
    const IdentificationOptions& naming = options.identification;
    const double own = cv::norm(at - predicted_at(i));
    for (size_t j = 0; j < states.size(); ++j) {
      if (j == i || states[j].spec->is_tag()) continue;
      if (states[j].valid && cv::norm(states[j].position - at) < 0.5 * spacing[j] * scale)
        return false;
      if (!states[j].valid && has_prediction[j] &&
          cv::norm(predicted_at(j) - at) < naming.unnamed_rival * own &&
          own > naming.sure_within * spacing[i] * scale)
        return false;
    }
    return true;
  }
};

MarkerTracker::MarkerTracker(MarkerLayout layout, TrackerOptions options)
    : impl_(std::make_unique<Impl>(std::move(layout), std::move(options))) {}

MarkerTracker::~MarkerTracker() = default;

void MarkerTracker::set_start_positions(const std::map<std::string, cv::Point2d>& positions) {
  impl_->start_positions = positions;
  impl_->started = false;
}

TrackedFrame MarkerTracker::track(const cv::Mat& image, long frame, double time_s) {
  Impl& m = *impl_;
  m.step_times.clear();
  m.to_gray(image);
  if (m.started) {
    // LK needs this frame's pyramid the size of the previous one: it moves with the markers.
    m.timed("pyramid", [&] {
      const cv::Rect need = m.needed_region();
      m.region = m.placed(m.previous_region.size(), need);
      m.ensure_gray(m.region);
      m.build_pyramid(m.region, m.pyramid);
    });
    m.follow();
    const long followed = frame - m.started_at;
    if (m.options.second_look_after > 0 && followed > 0 &&
        followed % m.options.second_look_after == 0 && m.start_positions.empty() &&
        m.looks < m.options.second_look_tries) {
      ++m.looks;
      if (m.timed("second_look", [&] { return m.second_look(frame); }))
        m.looks = m.options.second_look_tries;
    }
    // (Not on a frame the second look has just named afresh.)
    if (m.options.identity_check_every > 0 && followed % m.options.identity_check_every == 0 &&
        m.start_positions.empty() && m.started_at != frame)
      m.timed("check_identities", [&] { m.check_identities(); });
    bool any =
        std::any_of(m.states.begin(), m.states.end(), [](const MarkerState& s) { return s.valid; });
    if (!any) {
      m.started = false;  // everything lost: identify again from scratch
    } else {
      const cv::Rect now = m.needed_region();
      if (!m.fits(m.region.size(), now)) {
        m.region = m.placed(m.grown(now), now);
        m.ensure_gray(m.region);
        m.build_pyramid(m.region, m.pyramid);
      }
    }
  } else {
    m.start();
    if (m.started) {
      m.started_at = frame;
      m.looks = 0;
      m.moved_before.clear();
      m.note = m.start_positions.empty() ? "identified, " + describe(m.identification)
                                         : "started from the starting positions";
      const cv::Rect need = m.needed_region();
      m.region = m.placed(m.grown(need), need);
      m.build_pyramid(m.region, m.pyramid);
    }
  }
  std::swap(m.previous_pyramid, m.pyramid);
  m.previous_region = m.region;

  TrackedFrame out;
  out.frame = frame;
  out.time_s = time_s;
  out.identification = std::move(m.note);
  m.note.clear();
  for (MarkerState& s : m.states) {
    if (s.valid) s.lost_reason = LostReason::None;
    // Found again after being lost: its name was chosen by re-acquisition, not carried by LK.
    if (s.valid && s.lost_frames > 0 && m.started_at != frame)
      m.unconfirmed.insert(static_cast<size_t>(&s - m.states.data()));
    s.lost_frames = s.valid ? 0 : s.lost_frames + 1;
    if (!s.valid) s.quality = 0;
    MarkerObservation o;
    o.marker = s.spec->id;
    o.feature_point = s.spec->feature_point;
    o.valid = s.valid;
    o.position = s.valid ? s.position : cv::Point2d(std::nan(""), std::nan(""));
    o.quality = s.quality;
    out.markers.push_back(o);
  }
  return out;
}

void TrackerOptions::validate() const {
  dots.validate();
  identification.validate();
  eyes.validate();
  lower_lip.validate();
  OptionCheck("TrackerOptions")
      .positive("reference_dot_px", reference_dot_px)
      .positive("lk_window", lk_window)
      .not_negative("lk_levels", lk_levels)
      .not_negative("region_margin_px", region_margin_px)
      .positive("max_fb_error", max_fb_error)
      .positive("max_snap", max_snap)
      .not_negative("min_contrast_ratio", min_contrast_ratio)
      .not_negative("tag_margin", tag_margin)
      .not_negative("tag_decimate_above_px", tag_decimate_above_px)
      .positive("tag_redetect_every", tag_redetect_every)
      .positive("search_fraction", search_fraction)
      .not_negative("max_relative_motion", max_relative_motion)
      .not_negative("max_relative_motion_px", max_relative_motion_px)
      .not_negative("min_identified", min_identified)
      .not_negative("identity_check_every", identity_check_every)
      .not_negative("second_look_after", second_look_after)
      .at_least("second_look_tries", second_look_tries, 1)
      .not_negative("threads", threads);
}

void set_tracker_option(TrackerOptions& options, const std::string& assignment) {
  using O = TrackerOptions;
  static const std::vector<NamedOption<O>> table = {
      ROSTRO_NAMED_OPTION(O, dots.min_diameter_px),
      ROSTRO_NAMED_OPTION(O, dots.max_diameter_px),
      ROSTRO_NAMED_OPTION(O, dots.min_contrast),
      ROSTRO_NAMED_OPTION(O, dots.min_roundness),
      ROSTRO_NAMED_OPTION(O, dots.min_roundness_merged),
      ROSTRO_NAMED_OPTION(O, dots.max_elongation),
      ROSTRO_NAMED_OPTION(O, dots.max_surround),
      ROSTRO_NAMED_OPTION(O, dots.edge_fit),
      ROSTRO_NAMED_OPTION(O, dots.raise_share_for_roundness),
      ROSTRO_NAMED_OPTION(O, dots.symmetric_centre),
      ROSTRO_NAMED_OPTION(O, reference_dot_px),
      ROSTRO_NAMED_OPTION(O, edge_fit_elsewhere),
      ROSTRO_NAMED_OPTION(O, surround_test_upper_face_only),
      ROSTRO_NAMED_OPTION(O, brows.edge_fit_mid_brows),
      ROSTRO_NAMED_OPTION(O, eyes.inner_corners_raise_share),
      ROSTRO_NAMED_OPTION(O, eyes.inner_corners_symmetric_centre),
      ROSTRO_NAMED_OPTION(O, eyes.inner_corner_max_elongation_large),
      ROSTRO_NAMED_OPTION(O, lk_window),
      ROSTRO_NAMED_OPTION(O, lk_levels),
      ROSTRO_NAMED_OPTION(O, region_margin_px),
      ROSTRO_NAMED_OPTION(O, max_fb_error),
      ROSTRO_NAMED_OPTION(O, max_snap),
      ROSTRO_NAMED_OPTION(O, min_contrast_ratio),
      ROSTRO_NAMED_OPTION(O, tag_margin),
      ROSTRO_NAMED_OPTION(O, tag_decimate_above_px),
      ROSTRO_NAMED_OPTION(O, tag_redetect_every),
      ROSTRO_NAMED_OPTION(O, align_tags),
      ROSTRO_NAMED_OPTION(O, search_fraction),
      ROSTRO_NAMED_OPTION(O, found_look_allowance),
      ROSTRO_NAMED_OPTION(O, eyes.max_eye_snap),
      ROSTRO_NAMED_OPTION(O, eyes.lid_sideways_fraction),
      ROSTRO_NAMED_OPTION(O, eyes.lid_overshoot_fraction),
      ROSTRO_NAMED_OPTION(O, eyes.lid_reach),
      ROSTRO_NAMED_OPTION(O, max_relative_motion),
      ROSTRO_NAMED_OPTION(O, max_relative_motion_px),
      ROSTRO_NAMED_OPTION(O, lower_lip.together),
      ROSTRO_NAMED_OPTION(O, lower_lip.with_the_jaw),
      ROSTRO_NAMED_OPTION(O, start_place_when_found),
      ROSTRO_NAMED_OPTION(O, lower_lip.up),
      ROSTRO_NAMED_OPTION(O, lower_lip.down),
      ROSTRO_NAMED_OPTION(O, lower_lip.sideways),
      ROSTRO_NAMED_OPTION(O, lower_lip.shape),
      ROSTRO_NAMED_OPTION(O, eyes.max_dot_growth_found),
      ROSTRO_NAMED_OPTION(O, eyes.eye_size_memory_frames),
      ROSTRO_NAMED_OPTION(O, eyes.edge_on_elongation),
      ROSTRO_NAMED_OPTION(O, eyes.max_lid_elongation),
      ROSTRO_NAMED_OPTION(O, eyes.max_lid_surround),
      ROSTRO_NAMED_OPTION(O, min_identified),
      ROSTRO_NAMED_OPTION(O, identification.gate),
      ROSTRO_NAMED_OPTION(O, identification.size_factor),
      ROSTRO_NAMED_OPTION(O, identification.shape_factor),
      ROSTRO_NAMED_OPTION(O, identification.alone_share),
      ROSTRO_NAMED_OPTION(O, identification.ink_weight),
      ROSTRO_NAMED_OPTION(O, identification.lower_lip_apart),
      ROSTRO_NAMED_OPTION(O, identification.dots_beside_points),
      ROSTRO_NAMED_OPTION(O, identification.unnamed_rival),
      ROSTRO_NAMED_OPTION(O, identification.sure_within),
      ROSTRO_NAMED_OPTION(O, identification.min_explained),
      ROSTRO_NAMED_OPTION(O, identification.max_residual),
      ROSTRO_NAMED_OPTION(O, identification.min_margin),
      ROSTRO_NAMED_OPTION(O, identification.min_tags),
      ROSTRO_NAMED_OPTION(O, identification.max_tag_error),
      ROSTRO_NAMED_OPTION(O, identification.max_elongation),
      ROSTRO_NAMED_OPTION(O, identity_check_every),
      ROSTRO_NAMED_OPTION(O, second_look_after),
      ROSTRO_NAMED_OPTION(O, second_look_tries),
      ROSTRO_NAMED_OPTION(O, threads),
  };
  set_named_option(options, table, "TrackerOptions", assignment);
}

const char* to_string(LostReason r) {
  switch (r) {
    case LostReason::None:
      return "none";
    case LostReason::Unidentified:
      return "unidentified";
    case LostReason::RoundTrip:
      return "round trip";
    case LostReason::NoDot:
      return "no dot";
    case LostReason::Snap:
      return "snap";
    case LostReason::EyeSnap:
      return "eye snap";
    case LostReason::LidElongation:
      return "lid elongation";
    case LostReason::LidSurround:
      return "lid surround";
    case LostReason::Contrast:
      return "contrast";
    case LostReason::Shrunk:
      return "shrunk";
    case LostReason::Growth:
      return "growth";
    case LostReason::Jump:
      return "jump";
    case LostReason::Coincident:
      return "coincident";
    case LostReason::LidBand:
      return "lid band";
    case LostReason::Identity:
      return "identity";
    case LostReason::TagLost:
      return "tag lost";
  }
  return "?";
}

bool MarkerTracker::started() const {
  return impl_->started;
}
const IdentificationConfidence& MarkerTracker::identification() const {
  return impl_->identification;
}
long MarkerTracker::started_at() const {
  return impl_->started_at;
}
const std::vector<MarkerState>& MarkerTracker::states() const {
  return impl_->states;
}
const MarkerLayout& MarkerTracker::layout() const {
  return impl_->layout;
}
const std::vector<StepTime>& MarkerTracker::step_times() const {
  return impl_->step_times;
}
void MarkerTracker::draw(cv::Mat& image, long frame) const {
  draw_overlay(image, impl_->states, frame);
}

}  // namespace rostro::tracking
